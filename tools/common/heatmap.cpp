#include "heatmap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "image_io.h"

namespace obvh::tools {

void writeHeatmap(const std::string& path, int width, int height, const std::vector<float>& values) {
  if (width <= 0 || height <= 0 || values.size() != size_t(width) * size_t(height))
    throw std::invalid_argument("heatmap " + path + ": " + std::to_string(values.size()) + " values for " +
                                std::to_string(width) + "x" + std::to_string(height) + " pixels");
  static const float ramp[5][3] = {{0.f, 0.f, 0.15f}, {0.1f, 0.2f, 0.9f}, {0.9f, 0.1f, 0.1f}, {1.f, 0.9f, 0.1f}, {1.f, 1.f, 1.f}};
  std::vector<float> rgb(values.size() * 3);
  for (size_t i = 0; i < values.size(); ++i) {
    const float x = std::clamp(std::log(std::max(values[i], 1.f)) / std::log(256.f), 0.f, 1.f) * 4.f;
    const int k = std::min(int(x), 3);
    const float f = x - float(k);
    for (int c = 0; c < 3; ++c) rgb[3 * i + size_t(c)] = ramp[k][c] * (1.f - f) + ramp[k + 1][c] * f;
  }
  writeImage(path, width, height, rgb);
}

}  // namespace obvh::tools
