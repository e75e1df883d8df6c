// The AVX2 instantiation of the eight-wide oriented kernels; compiled as wide_traversal_avx2.cpp
// is (a target region after the shared headers, no FMA contraction), called only on CPUs with AVX2.
#include <cmath>
#include <limits>

#include "simd/double_lanes.h"
#include "simd/float4_sse.h"
#include "traversal/box_test.h"
#include "traversal/oriented_box_test.h"
#include "traversal/oriented_wide_traversal.h"
#include "traversal/triangle_block_leaf.h"
#include "traversal/wide_traversal.h"

#pragma GCC push_options
#pragma GCC target("avx2")

#include "simd/double4_avx.h"
#include "simd/float8_avx.h"
#include "traversal/oriented_wide_packets.h"
#include "traversal/oriented_wide_traverse.h"

namespace obvh {

bool intersectClosestOrientedWide(const TriangleOrientedWideView<8>& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters) {
  if (view.bvh->hasPalette)
    return intersectClosestOrientedWideImpl<simd::Float8Avx, simd::Float4Sse, true>(view, ray, hit, state, counters);
  return intersectClosestOrientedWideImpl<simd::Float8Avx, simd::Float4Sse>(view, ray, hit, state, counters);
}

bool intersectAnyOrientedWide(const TriangleOrientedWideView<8>& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters) {
  if (view.bvh->hasPalette)
    return intersectAnyOrientedWideImpl<simd::Float8Avx, simd::Float4Sse, true>(view, ray, state, counters);
  return intersectAnyOrientedWideImpl<simd::Float8Avx, simd::Float4Sse>(view, ray, state, counters);
}

uint32_t intersectClosestOrientedWidePacket(const TriangleOrientedWideView<8>& view, Ray* rays, Hit* hits,
                                            uint32_t active, const QueryState& state) {
  return intersectClosestOrientedWidePacketImpl<simd::Float8Avx, simd::Float4Sse>(view, rays, hits, active, state);
}

}  // namespace obvh

#pragma GCC pop_options
