#include "spectral.h"

#include <algorithm>
#include <cmath>

namespace obvh::render {
namespace {

float lobe(float x, float mean, float sigmaBelow, float sigmaAbove) {
  const float t = (x - mean) / (x < mean ? sigmaBelow : sigmaAbove);
  return std::exp(-0.5f * t * t);
}

float smoothStep(float edge0, float edge1, float x) {
  const float t = std::min(std::max((x - edge0) / (edge1 - edge0), 0.f), 1.f);
  return t * t * (3.f - 2.f * t);
}

// Linear sRGB of the flat spectrum over [400, 700] nm, averaged like the estimator averages it.
Vec3 flatSpectrumRgb() {
  Vec3 xyz{0.f};
  const int steps = 3000;
  for (int i = 0; i < steps; ++i)
    xyz += cieXyz(kShortestWavelength + (kLongestWavelength - kShortestWavelength) * (float(i) + 0.5f) / steps);
  return xyzToLinearSrgb(xyz / float(steps));
}

}  // namespace

Vec3 cieXyz(float w) {
  return {1.056f * lobe(w, 599.8f, 37.9f, 31.0f) + 0.362f * lobe(w, 442.0f, 16.0f, 26.7f) - 0.065f * lobe(w, 501.1f, 20.4f, 26.2f),
          0.821f * lobe(w, 568.8f, 46.9f, 40.5f) + 0.286f * lobe(w, 530.9f, 16.3f, 31.1f),
          1.217f * lobe(w, 437.0f, 11.8f, 36.0f) + 0.681f * lobe(w, 459.0f, 26.0f, 13.8f)};
}

Vec3 xyzToLinearSrgb(Vec3 c) {
  return {3.2406f * c.x - 1.5372f * c.y - 0.4986f * c.z, -0.9689f * c.x + 1.8758f * c.y + 0.0415f * c.z,
          0.0557f * c.x - 0.2040f * c.y + 1.0570f * c.z};
}

float rgbSpectrumAt(Vec3 rgb, float w) {
  const float red = smoothStep(570.f, 610.f, w);
  const float blue = 1.f - smoothStep(470.f, 510.f, w);
  return rgb.x * red + rgb.y * (1.f - red - blue) + rgb.z * blue;
}

Vec3 spectralSampleToRgb(float radiance, float w) {
  static const Vec3 white = flatSpectrumRgb();
  const Vec3 rgb = xyzToLinearSrgb(cieXyz(w) * radiance);
  return {rgb.x / white.x, rgb.y / white.y, rgb.z / white.z};
}

float iorAtWavelength(float ior, float dispersion, float w) {
  if (dispersion <= 0.f) return ior;
  const float abbe = 20.f / dispersion;
  return std::max(1.f, ior + (ior - 1.f) / abbe * (523655.f / (w * w) - 1.5168f));
}

}  // namespace obvh::render
