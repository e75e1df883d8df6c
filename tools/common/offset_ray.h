// Spawning secondary rays without self-intersection (Waechter and Binder, "A Fast and Robust
// Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019): the hit point is pushed off the
// surface along the geometric normal by a number of ulps that scales with its magnitude, and by a
// small absolute amount near the origin, where ulps are tiny.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace obvh::tools {

// p: a hit point; n: the unit geometric normal, pointing to the side the new ray leaves towards.
inline void offsetRayOrigin(const float p[3], const float n[3], float out[3]) {
  constexpr float kOrigin = 1.f / 32.f;
  constexpr float kFloatScale = 1.f / 65536.f;
  constexpr float kIntScale = 256.f;
  for (int axis = 0; axis < 3; ++axis) {
    const int32_t ulps = int32_t(kIntScale * n[axis]);
    int32_t bits;
    std::memcpy(&bits, &p[axis], sizeof bits);
    bits += p[axis] < 0.f ? -ulps : ulps;
    float moved;
    std::memcpy(&moved, &bits, sizeof moved);
    out[axis] = std::fabs(p[axis]) < kOrigin ? p[axis] + kFloatScale * n[axis] : moved;
  }
}

}  // namespace obvh::tools
