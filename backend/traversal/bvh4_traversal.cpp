#include "traversal/bvh4_traversal.h"

#include "simd/cpu_features.h"

namespace obvh {

KernelIsa bestKernelIsa() { return simd::cpuHasSse42() ? KernelIsa::Sse42 : KernelIsa::Scalar; }

bool intersectClosestBvh4(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Sse42 ? intersectClosestBvh4Sse42(bvh, ray, hit, state)
                                 : intersectClosestBvh4Scalar(bvh, ray, hit, state);
}

bool intersectAnyBvh4(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Sse42 ? intersectAnyBvh4Sse42(bvh, ray, state) : intersectAnyBvh4Scalar(bvh, ray, state);
}

}  // namespace obvh
