// Ray queries against wide triangle BVHs: accel=bvh4 (one SSE test per node covers four child
// boxes) and accel=bvh8 (one AVX2 test covers eight). Leaves are tested four triangles at a time.
// Every kernel also exists as a scalar reference; a CPU check picks the best one at run time.
#pragma once

#include <limits>

#include "builders/build_options.h"
#include "bvh/wide_bvh.h"
#include "traversal/query_entry.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

template <int N>
struct WideKernels;

template <int N>
struct TriangleWideView {
  const WideNode<N>* nodes = nullptr;
  const TriangleBlock4* blocks = nullptr;
  uint32_t root = WideNode<N>::kEmptyChild;
  TriangleSet set;
  const WideKernels<N>* kernels = nullptr;  // the CPU's best, chosen once per view, not per query
  float extent = 0.f;  // the largest side of the root node's box (packets judge their rays' spread by it)
  // The box around the root node's children (x, y, z, then a lane that admits every ray): single
  // rays that miss it are turned away before the node test's set-up (missesRootBox). The defaults
  // admit every ray.
  alignas(16) float rootLower[4] = {-kInfinity, -kInfinity, -kInfinity, -kInfinity};
  alignas(16) float rootUpper[4] = {kInfinity, kInfinity, kInfinity, kInfinity};
  static constexpr float kInfinity = std::numeric_limits<float>::infinity();
  bool empty() const { return root == WideNode<N>::kEmptyChild; }
};

// Packets: up to kMaxPacketSize rays, lane i active when bit i of active is set. The rays array
// has kMaxPacketSize entries (the kernels load whole lane groups); inactive ones are not read for
// their values and may be uninitialized.
constexpr int kMaxPacketSize = 16;

// Scalar: the reference kernels (FloatScalar). Simd: SSE4.2 for bvh4, AVX2 for bvh8.
enum class KernelIsa { Scalar, Simd };

// Simd when the CPU has the instruction set the layout's kernels need.
KernelIsa bestKernelIsa(int width);

// One instruction set's kernels for one width: closest hit and any hit, single rays and packets.
// Packet queries return the mask of lanes that hit (rays[i].tfar and hits[i] updated) or are occluded.
template <int N>
struct WideKernels {
  bool (*closest)(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state);
  bool (*any)(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state);
  uint32_t (*closestPacket)(const TriangleWideView<N>& bvh, Ray* rays, Hit* hits, uint32_t active,
                            const QueryState& state);
  uint32_t (*anyPacket)(const TriangleWideView<N>& bvh, const Ray* rays, uint32_t active, const QueryState& state);
  // closest and any, adding their box tests and leaf visits to *state.counters (must be set).
  bool (*closestCounted)(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state);
  bool (*anyCounted)(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state);
  // closest and any for rays the application declared coherent (QueryState::coherent): the same
  // answers, from a walk that lets the branch predictor guess the next child (wide_walk.h).
  bool (*closestCoherent)(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state);
  bool (*anyCoherent)(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state);
  // closest, closestCoherent, any, anyCoherent, closestPacket and anyPacket for a QueryEntry whose
  // target is the view (each jumps to its kernel).
  QueryEntry::Closest closestOfView[2];
  QueryEntry::Any anyOfView[2];
  QueryEntry::ClosestPacket closestPacketOfView;
  QueryEntry::AnyPacket anyPacketOfView;
};

// The entry of a view: its own kernels, or the empty structure's.
template <int N>
QueryEntry queryEntry(const TriangleWideView<N>& view) {
  QueryEntry entry;
  if (view.empty()) return entry;
  entry.target = &view;
  for (int coherent = 0; coherent < 2; ++coherent) {
    entry.closest[coherent] = view.kernels->closestOfView[coherent];
    entry.any[coherent] = view.kernels->anyOfView[coherent];
  }
  entry.closestPacket = view.kernels->closestPacketOfView;
  entry.anyPacket = view.kernels->anyPacketOfView;
  // makeWideView leaves the root box unbounded (infinite) for a leaf root.
  entry.packetGate.bounded = !WideNode<N>::isLeaf(view.root);
  for (int axis = 0; axis < 3; ++axis) {
    entry.packetGate.lower[axis] = view.rootLower[axis];
    entry.packetGate.upper[axis] = view.rootUpper[axis];
  }
  return entry;
}

// Defined in wide_traversal_<isa>.cpp, each compiled for its instruction set.
const WideKernels<4>& bvh4ScalarKernels(ChildOrder order);
const WideKernels<8>& bvh8ScalarKernels(ChildOrder order);
const WideKernels<4>& bvh4Sse42Kernels(ChildOrder order);
const WideKernels<8>& bvh8Avx2Kernels(ChildOrder order);

template <int N>
const WideKernels<N>& wideKernels(KernelIsa isa, ChildOrder order = ChildOrder::NearToFar) {
  if constexpr (N == 4) return isa == KernelIsa::Simd ? bvh4Sse42Kernels(order) : bvh4ScalarKernels(order);
  else return isa == KernelIsa::Simd ? bvh8Avx2Kernels(order) : bvh8ScalarKernels(order);
}

template <int N>
TriangleWideView<N> makeWideView(const WideBvh<N>& bvh, const TriangleSet& set,
                                 ChildOrder order = ChildOrder::NearToFar) {
  const Box3f rootBox = bvh.rootNodeBox();
  TriangleWideView<N> view{bvh.nodes.data(), bvh.blocks.data(), bvh.rootChild, set,
                           &wideKernels<N>(bestKernelIsa(N), order), rootBox.largestSide()};
  if (!bvh.empty() && !WideNode<N>::isLeaf(bvh.rootChild)) {
    for (int axis = 0; axis < 3; ++axis) {
      view.rootLower[axis] = rootBox.lower[axis];
      view.rootUpper[axis] = rootBox.upper[axis];
    }
  }
  return view;
}

// Both count into state.counters when it is set, and take the coherent walk when state.coherent
// is. Without an isa, the view's kernels run.
template <int N>
bool intersectClosestWide(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state,
                          const WideKernels<N>& k) {
  if (state.counters) return k.closestCounted(bvh, ray, hit, state);
  return state.coherent ? k.closestCoherent(bvh, ray, hit, state) : k.closest(bvh, ray, hit, state);
}
template <int N>
bool intersectClosestWide(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  return intersectClosestWide(bvh, ray, hit, state, *bvh.kernels);
}
template <int N>
bool intersectClosestWide(const TriangleWideView<N>& bvh, Ray& ray, Hit& hit, const QueryState& state, KernelIsa isa) {
  return intersectClosestWide(bvh, ray, hit, state, wideKernels<N>(isa));
}

template <int N>
bool intersectAnyWide(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state, const WideKernels<N>& k) {
  if (state.counters) return k.anyCounted(bvh, ray, state);
  return state.coherent ? k.anyCoherent(bvh, ray, state) : k.any(bvh, ray, state);
}
template <int N>
bool intersectAnyWide(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state) {
  return intersectAnyWide(bvh, ray, state, *bvh.kernels);
}
template <int N>
bool intersectAnyWide(const TriangleWideView<N>& bvh, const Ray& ray, const QueryState& state, KernelIsa isa) {
  return intersectAnyWide(bvh, ray, state, wideKernels<N>(isa));
}

template <int N>
uint32_t intersectClosestWidePacket(const TriangleWideView<N>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state) {
  return bvh.kernels->closestPacket(bvh, rays, hits, active, state);
}
template <int N>
uint32_t intersectClosestWidePacket(const TriangleWideView<N>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state, KernelIsa isa) {
  return wideKernels<N>(isa).closestPacket(bvh, rays, hits, active, state);
}

template <int N>
uint32_t intersectAnyWidePacket(const TriangleWideView<N>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state) {
  return bvh.kernels->anyPacket(bvh, rays, active, state);
}
template <int N>
uint32_t intersectAnyWidePacket(const TriangleWideView<N>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state, KernelIsa isa) {
  return wideKernels<N>(isa).anyPacket(bvh, rays, active, state);
}

}  // namespace obvh
