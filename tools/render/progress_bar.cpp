#include "progress_bar.h"

#include <cstdio>

namespace obvh::render {

ProgressBar::ProgressBar(std::string label, size_t total, bool enabled)
    : label_(std::move(label)), total_(total == 0 ? 1 : total), start_(std::chrono::steady_clock::now()) {
  if (!enabled) return;
  painter_ = std::thread([this] {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return stop_; }))
      if (std::chrono::steady_clock::now() - start_ > std::chrono::seconds(1)) draw(false);
  });
}

ProgressBar::~ProgressBar() {
  if (painter_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    painter_.join();
  }
  if (drawn_) draw(true);
}

void ProgressBar::draw(bool final) {
  const size_t done = final ? total_ : std::min(done_.load(std::memory_order_relaxed), total_);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double fraction = double(done) / double(total_);
  const int width = 30, filled = int(fraction * width);
  std::string bar(size_t(filled), '#');
  bar.append(size_t(width - filled), '.');
  if (final) {
    std::fprintf(stderr, "\r%s [%s] 100%%  %.1f s          \n", label_.c_str(), bar.c_str(), elapsed);
  } else {
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "\r%s [%s] %3d%%  ETA %.0f s   ", label_.c_str(), bar.c_str(), int(100 * fraction), eta);
  }
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace obvh::render
