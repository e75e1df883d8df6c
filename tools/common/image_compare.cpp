#include "image_compare.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace obvh::tools {

bool readImage(const std::string& path, Image& image, std::string& error) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    error = "cannot open '" + path + "': " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  image.width = spec.width, image.height = spec.height, image.channels = spec.nchannels;
  image.pixels.resize(size_t(image.width) * image.height * image.channels);
  if (!in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::FLOAT, image.pixels.data())) {
    error = "cannot read '" + path + "': " + in->geterror();
    return false;
  }
  return true;
}

ImageDifference compareImages(const Image& a, const Image& b, double tolerance) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw std::invalid_argument("compareImages: the images differ in size");
  ImageDifference d;
  d.pixels = size_t(a.width) * a.height;
  double sum = 0.0, squares = 0.0;
  for (size_t p = 0; p < d.pixels; ++p) {
    double largest = 0.0;
    for (int c = 0; c < a.channels; ++c) {
      const double e = std::fabs(double(a.pixels[p * a.channels + c]) - double(b.pixels[p * a.channels + c]));
      largest = std::max(largest, e);
      sum += e, squares += e * e;
    }
    d.maxError = std::max(d.maxError, largest);
    if (largest > tolerance) d.differing.push_back(p);
  }
  d.differingPixels = d.differing.size();
  const double values = double(d.pixels) * std::max(a.channels, 1);
  d.meanError = values > 0 ? sum / values : 0.0;
  if (squares > 0.0) d.psnr = 10.0 * std::log10(values / squares);
  return d;
}

}  // namespace obvh::tools
