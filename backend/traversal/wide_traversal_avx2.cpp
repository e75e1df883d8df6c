// The AVX2 instantiation of the eight-wide kernels (compiled with -mavx2 and without FMA
// contraction, so every lane rounds exactly like the scalar reference).
#include "simd/float4_sse.h"
#include "simd/float8_avx.h"
#include "traversal/wide_traverse.h"

namespace obvh {

bool intersectClosestBvh8Avx2(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestWideImpl<simd::Float8Avx, simd::Float4Sse>(bvh, ray, hit, state);
}

bool intersectAnyBvh8Avx2(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyWideImpl<simd::Float8Avx, simd::Float4Sse>(bvh, ray, state);
}


uint32_t intersectClosestBvh8PacketAvx2(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                   const QueryState& state) {
  return intersectClosestWidePacketImpl<simd::Float8Avx, simd::Float4Sse>(bvh, rays, hits, active, state);
}

uint32_t intersectAnyBvh8PacketAvx2(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                               const QueryState& state) {
  return intersectAnyWidePacketImpl<simd::Float8Avx, simd::Float4Sse>(bvh, rays, active, state);
}

}  // namespace obvh
