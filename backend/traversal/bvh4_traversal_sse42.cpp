// The SSE instantiation of the four-wide kernels (compiled with -msse4.2).
#include "simd/float4.h"
#include "traversal/bvh4_traverse.h"

namespace obvh {

bool intersectClosestBvh4Sse42(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestBvh4Impl<simd::Float4Sse>(bvh, ray, hit, state);
}

bool intersectAnyBvh4Sse42(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyBvh4Impl<simd::Float4Sse>(bvh, ray, state);
}

}  // namespace obvh
