// Random unit vectors for the kernels' randomized tests (normal samples normalized: every direction
// equally likely, none near zero length).
#pragma once

#include <cmath>
#include <random>

#include "math/vec3.h"

namespace obvh::test {

inline Vec3f randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> normal;
  for (;;) {
    const Vec3f d{normal(rng), normal(rng), normal(rng)};
    const float length = std::sqrt(dot(d, d));
    if (length > 1e-3f) return d * (1.f / length);
  }
}

}  // namespace obvh::test
