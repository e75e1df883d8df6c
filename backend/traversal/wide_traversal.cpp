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

uint32_t intersectClosestWidePacket(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectClosestBvh4PacketSse42(bvh, rays, hits, active, state)
                                : intersectClosestBvh4PacketScalar(bvh, rays, hits, active, state);
}

uint32_t intersectAnyWidePacket(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectAnyBvh4PacketSse42(bvh, rays, active, state)
                                : intersectAnyBvh4PacketScalar(bvh, rays, active, state);
}

uint32_t intersectClosestWidePacket(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectClosestBvh8PacketAvx2(bvh, rays, hits, active, state)
                                : intersectClosestBvh8PacketScalar(bvh, rays, hits, active, state);
}

uint32_t intersectAnyWidePacket(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state, KernelIsa isa) {
  return isa == KernelIsa::Simd ? intersectAnyBvh8PacketAvx2(bvh, rays, active, state)
                                : intersectAnyBvh8PacketScalar(bvh, rays, active, state);
}

}  // namespace obvh
