// Motion blur's time steps: where a time falls among a geometry's steps, spread evenly over its
// time range [start, end] as Embree spreads them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace obvh {

// Steps `segment` and `segment + 1` blended by f (0 at the first, 1 at the second).
struct TimeSegment {
  int segment = 0;
  float f = 0.f;
};

// False when `time` lies outside [start, end]: the geometry is not there then. stepCount >= 2.
inline bool timeSegment(float time, float start, float end, uint32_t stepCount, TimeSegment& out) {
  const float local = end > start ? (time - start) / (end - start) : (time == start ? 0.f : -1.f);
  if (!(local >= 0.f && local <= 1.f)) return false;
  const float ftime = local * float(stepCount - 1);
  out.segment = std::clamp(int(std::floor(ftime)), 0, int(stepCount) - 2);
  out.f = ftime - float(out.segment);
  return true;
}

}  // namespace obvh
