// The backend's own ray and hit records; the API layer converts Embree's structs to and from them.
#pragma once

#include <cstdint>
#include <limits>

#include "math/vec3.h"

namespace obvh {

constexpr uint32_t kInvalidId = 0xFFFFFFFFu;

// Laid out as the first 40 bytes of Embree's RTCRay (org, tnear, dir, time, tfar, mask), so that the
// API takes a single ray over as one copy (api/src/query_dispatch.h checks the offsets).
struct Ray {
  Vec3f org;
  float tnear = 0.f;  // hits must lie strictly beyond tnear
  Vec3f dir;
  float time = 0.f;   // in the shutter interval: where motion-blurred geometry is seen
  float tfar = 0.f;   // hits may lie at tfar; shrinks to the closest hit found so far
  uint32_t mask = 0xFFFFFFFFu;
};

// A ray from org along dir over the segment (tnear, tfar].
inline Ray rayAlong(Vec3f org, Vec3f dir, float tnear = 0.f, float tfar = std::numeric_limits<float>::infinity()) {
  Ray ray;
  ray.org = org;
  ray.dir = dir;
  ray.tnear = tnear;
  ray.tfar = tfar;
  return ray;
}

// Laid out as Embree's RTCHit (Ng, u, v, primID, geomID, instID), so that the API hands a hit
// over as one copy (api/src/query_dispatch.h checks the offsets).
struct Hit {
  Vec3f Ng;  // unnormalized, in Embree's orientation
  float u = 0.f, v = 0.f;
  uint32_t primID = kInvalidId;
  uint32_t geomID = kInvalidId;
  uint32_t instID = kInvalidId;  // the instance the hit was found through, if any
};

}  // namespace obvh
