#include "frame_output.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "mesh_loader.h"

namespace obvh::render {

unsigned char displayValue(float linear, float exposure) {
  float c = linear * std::exp2(exposure);
  c = std::min(std::max(c, 0.f), 1.f);
  const float encoded = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
  return static_cast<unsigned char>(std::lround(encoded * 255.f));
}

void writeFrame(const std::string& path, const Frame& frame, float exposure) {
  const std::string extension = tools::lowerCaseExtension(path);
  const bool linear = extension == "exr" || extension == "hdr";
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error("cannot write image '" + path + "': " + OIIO::geterror());
  OIIO::ImageSpec spec(frame.width, frame.height, 3, linear ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::UINT8);
  if (extension == "exr") spec.attribute("compression", "zip");
  if (!out->open(path, spec)) throw std::runtime_error("cannot write image '" + path + "': " + out->geterror());
  bool written = false;
  if (linear) {
    std::vector<float> scaled(frame.rgb);
    for (float& c : scaled) c *= std::exp2(exposure);
    written = out->write_image(OIIO::TypeDesc::FLOAT, scaled.data());
  } else {
    std::vector<unsigned char> bytes(frame.rgb.size());
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = displayValue(frame.rgb[i], exposure);
    written = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!written) throw std::runtime_error("cannot write image '" + path + "': " + out->geterror());
  out->close();
}

}  // namespace obvh::render
