// Writes a rendered frame through OpenImageIO: EXR (and HDR) keep linear half/float radiance;
// other formats (PNG, JPEG, PPM...) get the exposure, clamping and the sRGB transfer curve.
#pragma once

#include <string>

#include "renderer.h"

namespace obvh::render {

// exposure: stops applied before display encoding. Throws std::runtime_error naming the problem.
void writeFrame(const std::string& path, const Frame& frame, float exposure = 0.f);

// The 8-bit sRGB value a linear radiance is displayed as.
unsigned char displayValue(float linear, float exposure = 0.f);

}  // namespace obvh::render
