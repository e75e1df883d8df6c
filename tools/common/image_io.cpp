#include "image_io.h"

#include <OpenImageIO/imageio.h>

#include <stdexcept>

namespace obvh::tools {

void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw std::runtime_error("cannot create image '" + path + "': " + OIIO::geterror());
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  if (!out->open(path, spec)) throw std::runtime_error("cannot open image '" + path + "': " + out->geterror());
  if (!out->write_image(OIIO::TypeDesc::FLOAT, rgb.data()))
    throw std::runtime_error("cannot write image '" + path + "': " + out->geterror());
  out->close();
}

}  // namespace obvh::tools
