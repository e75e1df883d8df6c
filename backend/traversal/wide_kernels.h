// The kernel table of one pair of vector types (node width FN, four-lane triangle type F4): single
// rays and packets, closest and any hit. Each per-ISA file instantiates it inside its target region.
#pragma once

#include "traversal/wide_traverse.h"
#include "traversal/wide_traverse_packets.h"

namespace obvh {

// A kernel called through QueryEntry, whose target is the view.
template <int N, auto kKernel>
bool closestOfView(const void* view, Ray& ray, Hit& hit, const QueryState& state) {
  return kKernel(*static_cast<const TriangleWideView<N>*>(view), ray, hit, state);
}
template <int N, auto kKernel>
bool anyOfView(const void* view, const Ray& ray, const QueryState& state) {
  return kKernel(*static_cast<const TriangleWideView<N>*>(view), ray, state);
}
template <int N, auto kKernel>
uint32_t closestPacketOfView(const void* view, Ray* rays, Hit* hits, uint32_t active, const QueryState& state) {
  return kKernel(*static_cast<const TriangleWideView<N>*>(view), rays, hits, active, state);
}
template <int N, auto kKernel>
uint32_t anyPacketOfView(const void* view, const Ray* rays, uint32_t active, const QueryState& state) {
  return kKernel(*static_cast<const TriangleWideView<N>*>(view), rays, active, state);
}

// One table per child order of closest-hit single rays (packets and any-hit queries are the same
// in both).
template <typename FN, typename F4>
const WideKernels<FN::kWidth>& makeWideKernels(ChildOrder order) {
  constexpr int N = FN::kWidth;
  static const WideKernels<FN::kWidth> nearToFar{&intersectClosestWideImpl<FN, F4>,
                                                 &intersectAnyWideImpl<FN, F4>,
                                                 &intersectClosestWidePacketImpl<FN, F4>,
                                                 &intersectAnyWidePacketImpl<FN, F4>,
                                                 &intersectClosestWideImpl<FN, F4, true>,
                                                 &intersectAnyWideImpl<FN, F4, true>,
                                                 &intersectClosestWideImpl<FN, F4, false, true, true>,
                                                 &intersectAnyWideImpl<FN, F4, false, true>,
                                                 {&closestOfView<N, &intersectClosestWideImpl<FN, F4>>,
                                                  &closestOfView<N, &intersectClosestWideImpl<FN, F4, false, true, true>>},
                                                 {&anyOfView<N, &intersectAnyWideImpl<FN, F4>>,
                                                  &anyOfView<N, &intersectAnyWideImpl<FN, F4, false, true>>},
                                                 &closestPacketOfView<N, &intersectClosestWidePacketImpl<FN, F4>>,
                                                 &anyPacketOfView<N, &intersectAnyWidePacketImpl<FN, F4>>};
  static const WideKernels<FN::kWidth> laneOrder{&intersectClosestWideImpl<FN, F4, false, false>,
                                                 &intersectAnyWideImpl<FN, F4>,
                                                 &intersectClosestWidePacketImpl<FN, F4>,
                                                 &intersectAnyWidePacketImpl<FN, F4>,
                                                 &intersectClosestWideImpl<FN, F4, true, false>,
                                                 &intersectAnyWideImpl<FN, F4, true>,
                                                 &intersectClosestWideImpl<FN, F4, false, false, true>,
                                                 &intersectAnyWideImpl<FN, F4, false, true>,
                                                 {&closestOfView<N, &intersectClosestWideImpl<FN, F4, false, false>>,
                                                  &closestOfView<N, &intersectClosestWideImpl<FN, F4, false, false, true>>},
                                                 {&anyOfView<N, &intersectAnyWideImpl<FN, F4>>,
                                                  &anyOfView<N, &intersectAnyWideImpl<FN, F4, false, true>>},
                                                 &closestPacketOfView<N, &intersectClosestWidePacketImpl<FN, F4>>,
                                                 &anyPacketOfView<N, &intersectAnyWidePacketImpl<FN, F4>>};
  return order == ChildOrder::NearToFar ? nearToFar : laneOrder;
}

}  // namespace obvh
