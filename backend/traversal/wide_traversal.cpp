#include "traversal/wide_traversal.h"

#include "simd/cpu_features.h"

namespace obvh {

KernelIsa bestKernelIsa(int width) {
  const bool simd = width == 8 ? simd::cpuHasAvx2() : simd::cpuHasSse42();
  return simd ? KernelIsa::Simd : KernelIsa::Scalar;
}

bool intersectClosestWide(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectClosestBvh4Sse42(bvh, ray, hit, state)
                                : intersectClosestBvh4Scalar(bvh, ray, hit, state);
}

bool intersectAnyWide(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectAnyBvh4Sse42(bvh, ray, state) : intersectAnyBvh4Scalar(bvh, ray, state);
}

bool intersectClosestWide(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectClosestBvh8Avx2(bvh, ray, hit, state)
                                : intersectClosestBvh8Scalar(bvh, ray, hit, state);
}

bool intersectAnyWide(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectAnyBvh8Avx2(bvh, ray, state) : intersectAnyBvh8Scalar(bvh, ray, state);
}

}  // namespace obvh
