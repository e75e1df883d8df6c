// Ray queries against a four-wide triangle BVH (accel=bvh4): one SIMD test per node covers the four
// child boxes. The kernels exist as a scalar reference and as SSE; a CPU check picks one at run time.
#pragma once

#include "bvh/bvh4.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

struct TriangleBvh4View {
  const Bvh4Node* nodes = nullptr;
  uint32_t root = Bvh4Node::kEmptyChild;
  TriangleSet set;
  bool empty() const { return root == Bvh4Node::kEmptyChild; }
};

enum class KernelIsa { Scalar, Sse42 };

// The kernel set the CPU supports best (or the one forced for tests).
KernelIsa bestKernelIsa();

bool intersectClosestBvh4(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state,
                          KernelIsa isa = bestKernelIsa());
bool intersectAnyBvh4(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state,
                      KernelIsa isa = bestKernelIsa());

// Per-ISA entry points (defined in bvh4_traversal_<isa>.cpp).
bool intersectClosestBvh4Scalar(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh4Scalar(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state);
bool intersectClosestBvh4Sse42(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state);
bool intersectAnyBvh4Sse42(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state);

}  // namespace obvh
