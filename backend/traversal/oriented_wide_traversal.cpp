// The SSE instantiation of the four-wide oriented kernels (SSE2: baseline x86-64).
#include "traversal/oriented_wide_traversal.h"

#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "traversal/oriented_wide_traverse.h"

namespace obvh {

int fastestOrientedWidth() { return simd::cpuHasAvx2() ? 8 : 4; }

bool intersectClosestOrientedWide(const TriangleOrientedWideView<4>& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters) {
  return intersectClosestOrientedWideImpl<simd::Float4Sse, simd::Float4Sse>(view, ray, hit, state, counters);
}

bool intersectAnyOrientedWide(const TriangleOrientedWideView<4>& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters) {
  return intersectAnyOrientedWideImpl<simd::Float4Sse, simd::Float4Sse>(view, ray, state, counters);
}

}  // namespace obvh
