// Ray queries against wide triangle BVHs: accel=bvh4 (one SSE test per node covers four child
// boxes) and accel=bvh8 (one AVX2 test covers eight). Leaves are tested four triangles at a time.
// Every kernel also exists as a scalar reference; a CPU check picks the best one at run time.
#pragma once

#include "bvh/wide_bvh.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

template <int N>
struct TriangleWideView {
  const WideNode<N>* nodes = nullptr;
  const TriangleBlock4* blocks = nullptr;
  uint32_t root = WideNode<N>::kEmptyChild;
  TriangleSet set;
  bool empty() const { return root == WideNode<N>::kEmptyChild; }
};

template <int N>
TriangleWideView<N> makeWideView(const WideBvh<N>& bvh, const TriangleSet& set) {
  return {bvh.nodes.data(), bvh.blocks.data(), bvh.rootChild, set};
}

// Packets: up to kMaxPacketSize rays, lane i active when bit i of active is set.
constexpr int kMaxPacketSize = 16;

// Scalar: the reference kernels (FloatScalar). Simd: SSE4.2 for bvh4, AVX2 for bvh8.
enum class KernelIsa { Scalar, Simd };

// Simd when the CPU has the instruction set the layout's kernels need.
KernelIsa bestKernelIsa(int width);

bool intersectClosestWide(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state,
                          KernelIsa isa = bestKernelIsa(4));
bool intersectAnyWide(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state,
                      KernelIsa isa = bestKernelIsa(4));
bool intersectClosestWide(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state,
                          KernelIsa isa = bestKernelIsa(8));
bool intersectAnyWide(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state,
                      KernelIsa isa = bestKernelIsa(8));

// Packet queries: return the mask of lanes that hit (closest hit: rays[i].tfar and hits[i] updated)
// or are occluded.
uint32_t intersectClosestWidePacket(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state, KernelIsa isa = bestKernelIsa(4));
uint32_t intersectAnyWidePacket(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state, KernelIsa isa = bestKernelIsa(4));
uint32_t intersectClosestWidePacket(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                    const QueryState& state, KernelIsa isa = bestKernelIsa(8));
uint32_t intersectAnyWidePacket(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                                const QueryState& state, KernelIsa isa = bestKernelIsa(8));

// Per-ISA entry points (defined in wide_traversal_<isa>.cpp).
bool intersectClosestBvh4Scalar(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh4Scalar(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state);
bool intersectClosestBvh8Scalar(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh8Scalar(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state);
bool intersectClosestBvh4Sse42(const TriangleWideView<4>& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh4Sse42(const TriangleWideView<4>& bvh, const Ray& ray, const QueryState& state);
bool intersectClosestBvh8Avx2(const TriangleWideView<8>& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh8Avx2(const TriangleWideView<8>& bvh, const Ray& ray, const QueryState& state);

uint32_t intersectClosestBvh4PacketScalar(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                          const QueryState& state);
uint32_t intersectAnyBvh4PacketScalar(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                                      const QueryState& state);
uint32_t intersectClosestBvh8PacketScalar(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                          const QueryState& state);
uint32_t intersectAnyBvh8PacketScalar(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                                      const QueryState& state);
uint32_t intersectClosestBvh4PacketSse42(const TriangleWideView<4>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                         const QueryState& state);
uint32_t intersectAnyBvh4PacketSse42(const TriangleWideView<4>& bvh, const Ray* rays, uint32_t active,
                                     const QueryState& state);
uint32_t intersectClosestBvh8PacketAvx2(const TriangleWideView<8>& bvh, Ray* rays, Hit* hits, uint32_t active,
                                        const QueryState& state);
uint32_t intersectAnyBvh8PacketAvx2(const TriangleWideView<8>& bvh, const Ray* rays, uint32_t active,
                                    const QueryState& state);

}  // namespace obvh
