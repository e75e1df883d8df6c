// Whether a single ray follows the previous one traced on the same thread closely: camera rays of
// neighbouring pixels, shadow rays from neighbouring points to one light. Such rays take the same
// paths through a tree, which the branch predictor learns, so the oriented layouts' walks let it
// guess the next child for them (wide_walk.h, kPredictLanes); incoherent rays (random, diffuse,
// from a point source in all directions) would pay for its wrong guesses and walk as before.
#pragma once

#include "intersect/ray.h"

namespace obvh {

struct PreviousRay {
  Vec3f org{0.f, 0.f, 0.f};
  Vec3f dir{0.f, 0.f, 0.f};
  float dirLengthSquared = 0.f;
};

// One record a thread, shared by every scene and layout: a stream of rays alternating between two
// scenes reads as incoherent, which costs it the guesses, never an answer. Reached through the
// default TLS dialect's call to __tls_get_addr, which the compiler treats as any call (the
// kernel's vector registers are saved around it). Not through TLS descriptors
// (-mtls-dialect=gnu2, used here until 2026-11-27): their call is assumed to preserve every
// register, but a thread's first access takes glibc's slow path, which allocates the thread's
// block with malloc, and on this Debian 12 (glibc 2.36) the first ray of a thread lost vector
// registers there and could miss a hit: after the shared walk (wide_walk.h) was restructured, an
// oriented layouts' crossval test missed a hit on its first ray in about a third of the runs,
// depending on the address layout; with the default dialect, 0 of 9. Nor initial-exec: the
// benchmark loads two copies of the library (libobvh.so and the drop-in libembree3.so.3) next to
// Debian's Embree, and the static TLS block had no room left for the second copy.
inline thread_local PreviousRay previousRay;

// True when the ray starts within 1/32 of sceneExtent (the largest side of the scene's box) of the
// previous ray's origin and points within about 2.6 degrees of its direction (cos^2 >= 0.998);
// records the ray as the previous one. A ray with a NaN coordinate follows nothing, nor does the
// ray after it. Either answer only picks a walk: both give the same hits.
inline bool followsPreviousRay(const Ray& ray, float sceneExtent) {
  PreviousRay* record = &previousRay;
  // One look-up of the thread's record: GCC otherwise repeats it (a call to __tls_get_addr when
  // the library was loaded with dlopen) in each branch that stores the ray.
  asm("" : "+r"(record));
  PreviousRay& previous = *record;
  const Vec3f offset = ray.org - previous.org;
  const float dot = ray.dir.x * previous.dir.x + ray.dir.y * previous.dir.y + ray.dir.z * previous.dir.z;
  const float lengthSquared = ray.dir.x * ray.dir.x + ray.dir.y * ray.dir.y + ray.dir.z * ray.dir.z;
  const float near = sceneExtent * (1.f / 32.f);
  // One branch on all three, not one each: for rays from one point in random directions the
  // origins always agree and the direction's sign is a coin toss, which cost them 5% as a branch.
  const bool follows = (offset.x * offset.x + offset.y * offset.y + offset.z * offset.z <= near * near) &
                       (dot > 0.f) & (dot * dot >= 0.998f * lengthSquared * previous.dirLengthSquared);
  previous.org = ray.org;
  previous.dir = ray.dir;
  previous.dirLengthSquared = lengthSquared;
  return follows;
}

// Whether the walk should let the branch predictor guess (see above). Empty segments (tnear >
// tfar: shadow rays of pixels that missed) enter nothing and return before any guess; the check
// is skipped for them, as is the record, which they would only break.
inline bool worthPredicting(const Ray& ray, float sceneExtent) {
  return ray.tnear <= ray.tfar && followsPreviousRay(ray, sceneExtent);
}

}  // namespace obvh
