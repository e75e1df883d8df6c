#include "renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>

#include "progress_bar.h"

namespace obvh::render {

Vec3 renderPixel(const Integrator& integrator, const ViewCamera& camera, const FrameSettings& settings, int x, int y,
                 uint64_t& rays) {
  const uint64_t pixel = uint64_t(y) * uint64_t(settings.width) + uint64_t(x);
  Vec3 sum{0.f};
  for (int s = 0; s < settings.samplesPerPixel; ++s) {
    Sampler sampler(pixel, uint64_t(s), settings.frame);
    float px = float(x) + 0.5f, py = float(y) + 0.5f;
    if (settings.samplesPerPixel > 1) px = float(x) + sampler.next1D(), py = float(y) + sampler.next1D();
    Vec3 org, dir;
    camera.ray(px, py, settings.width, settings.height, org, dir);
    const float spectralU = (float(s) + sampler.next1D()) / float(settings.samplesPerPixel);
    sum += integrator.radiance(org, dir, sampler, spectralU, rays);
  }
  return sum / float(settings.samplesPerPixel);
}

Frame renderFrame(const Integrator& integrator, const ViewCamera& camera, const FrameSettings& settings) {
  Frame frame;
  frame.width = settings.width, frame.height = settings.height;
  frame.rgb.assign(size_t(settings.width) * settings.height * 3, 0.f);
  const tools::RtcLibrary& lib = integrator.library();
  if (settings.heatmap && !lib.obvhEnableTraversalStatistics)
    throw std::runtime_error("a heatmap needs obvh's traversal statistics; " + lib.path +
                             " does not count bounding-volume tests");
  if (settings.heatmap) frame.volumeTests.assign(size_t(settings.width) * settings.height, 0.f);
  tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
  ProgressBar progress("render", size_t(settings.height), settings.progress);
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<int>(0, settings.height), [&](const tbb::blocked_range<int>& rows) {
    uint64_t& count = rays.local();
    if (settings.heatmap) lib.obvhEnableTraversalStatistics(1);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < settings.width; ++x) {
        const Vec3 mean = renderPixel(integrator, camera, settings, x, y, count);
        const size_t pixel = size_t(y) * size_t(settings.width) + size_t(x);
        if (settings.heatmap) {
          ObvhTraversalStatistics statistics;
          lib.obvhTakeTraversalStatistics(&statistics);
          frame.volumeTests[pixel] = float(statistics.boundingVolumeTests);
        }
        float* out = &frame.rgb[pixel * 3];
        out[0] = mean.x, out[1] = mean.y, out[2] = mean.z;
      }
      progress.advance();
    }
    if (settings.heatmap) lib.obvhEnableTraversalStatistics(0);
  });
  frame.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  frame.rays = rays.combine([](uint64_t a, uint64_t b) { return a + b; });
  return frame;
}

}  // namespace obvh::render
