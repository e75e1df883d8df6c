// The scalar reference instantiation of the four-wide kernels.
#include "simd/float4.h"
#include "traversal/bvh4_traverse.h"

namespace obvh {

bool intersectClosestBvh4Scalar(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestBvh4Impl<simd::Float4Scalar>(bvh, ray, hit, state);
}

bool intersectAnyBvh4Scalar(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyBvh4Impl<simd::Float4Scalar>(bvh, ray, state);
}

}  // namespace obvh
