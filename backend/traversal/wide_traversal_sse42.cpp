// The SSE instantiation of the four-wide kernels (compiled with -msse4.2).
#include "simd/float4_sse.h"
#include "traversal/wide_traverse.h"

namespace obvh {

bool intersectClosestBvh4Sse42(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestWideImpl<simd::Float4Sse, simd::Float4Sse>(bvh, ray, hit, state);
}

bool intersectAnyBvh4Sse42(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyWideImpl<simd::Float4Sse, simd::Float4Sse>(bvh, ray, state);
}


uint32_t intersectClosestBvh4PacketSse42(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                   const QueryState& state) {
  return intersectClosestWidePacketImpl<simd::Float4Sse, simd::Float4Sse>(bvh, rays, hits, active, state);
}

uint32_t intersectAnyBvh4PacketSse42(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                               const QueryState& state) {
  return intersectAnyWidePacketImpl<simd::Float4Sse, simd::Float4Sse>(bvh, rays, active, state);
}

}  // namespace obvh
