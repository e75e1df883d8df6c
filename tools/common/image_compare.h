// Pixel-by-pixel image comparison (the obvh_imgdiff tool and the render cross-validation).
#pragma once

#include <string>
#include <vector>

namespace obvh::tools {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  // as OpenImageIO reads them: 8-bit values scaled to [0, 1]
};

// Returns false with a message naming the file when it cannot be read.
bool readImage(const std::string& path, Image& image, std::string& error);

constexpr double kIdenticalPsnr = 1e9;

struct ImageDifference {
  size_t pixels = 0;
  size_t differingPixels = 0;  // largest channel difference above the tolerance
  double maxError = 0.0;       // largest per-channel difference
  double meanError = 0.0;      // mean absolute per-channel difference
  double psnr = kIdenticalPsnr;  // 10 log10(1 / MSE) over all channels; kIdenticalPsnr when equal
  std::vector<size_t> differing;  // indices of the differing pixels
};

// Both images must have the same size and channel count.
ImageDifference compareImages(const Image& a, const Image& b, double tolerance);

}  // namespace obvh::tools
