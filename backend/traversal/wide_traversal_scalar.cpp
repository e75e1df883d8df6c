// The scalar reference instantiations of the wide kernels.
#include "simd/float_scalar.h"
#include "traversal/wide_traverse.h"

namespace obvh {

using simd::Float4Scalar;
using simd::Float8Scalar;

bool intersectClosestBvh4Scalar(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestWideImpl<Float4Scalar, Float4Scalar>(bvh, ray, hit, state);
}

bool intersectAnyBvh4Scalar(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyWideImpl<Float4Scalar, Float4Scalar>(bvh, ray, state);
}

bool intersectClosestBvh8Scalar(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestWideImpl<Float8Scalar, Float4Scalar>(bvh, ray, hit, state);
}

bool intersectAnyBvh8Scalar(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyWideImpl<Float8Scalar, Float4Scalar>(bvh, ray, state);
}


uint32_t intersectClosestBvh4PacketScalar(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                   const QueryState& state) {
  return intersectClosestWidePacketImpl<Float4Scalar, Float4Scalar>(bvh, rays, hits, active, state);
}

uint32_t intersectAnyBvh4PacketScalar(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                               const QueryState& state) {
  return intersectAnyWidePacketImpl<Float4Scalar, Float4Scalar>(bvh, rays, active, state);
}

uint32_t intersectClosestBvh8PacketScalar(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                   const QueryState& state) {
  return intersectClosestWidePacketImpl<Float8Scalar, Float4Scalar>(bvh, rays, hits, active, state);
}

uint32_t intersectAnyBvh8PacketScalar(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                               const QueryState& state) {
  return intersectAnyWidePacketImpl<Float8Scalar, Float4Scalar>(bvh, rays, active, state);
}

}  // namespace obvh
