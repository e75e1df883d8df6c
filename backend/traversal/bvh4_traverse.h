// Generic four-wide traversal, templated on the vector type (simd/float4.h). Included only by the
// per-ISA translation units.
#pragma once

#include <cmath>
#include <limits>

#include "traversal/box_test.h"
#include "traversal/bvh4_traversal.h"

namespace obvh {

template <typename F4>
struct Ray4Frame {
  F4 org[3], invDir[3];
  bool zero[3];      // axes along which the ray does not move
  float orgScalar[3];

  explicit Ray4Frame(const Ray& ray) {
    for (int axis = 0; axis < 3; ++axis) {
      zero[axis] = ray.dir[axis] == 0.f;
      orgScalar[axis] = ray.org[axis];
      org[axis] = F4::broadcast(ray.org[axis]);
      invDir[axis] = F4::broadcast(zero[axis] ? 0.f : 1.f / ray.dir[axis]);
    }
  }
};

// Tests the four child boxes; returns a bit mask of the entered ones and their entry distances.
// A ray that does not move along an axis is inside that slab exactly when its origin lies within
// [lower, upper] (inclusive), as in the scalar box test; the conservative far scaling is Ize's.
template <typename F4>
inline int intersectNode4(const Bvh4Node& node, const Ray4Frame<F4>& r, float tnear, float tfar, float entry[4]) {
  F4 nearT = F4::broadcast(tnear);
  F4 farT = F4::broadcast(std::numeric_limits<float>::infinity());
  int inside = 0xF;
  for (int axis = 0; axis < 3; ++axis) {
    const F4 lower = F4::load(node.bounds[axis * 2]);
    const F4 upper = F4::load(node.bounds[axis * 2 + 1]);
    if (r.zero[axis]) {
      inside &= lessEqualMask(lower, r.org[axis]) & lessEqualMask(r.org[axis], upper);
      continue;
    }
    const F4 t0 = (lower - r.org[axis]) * r.invDir[axis];
    const F4 t1 = (upper - r.org[axis]) * r.invDir[axis];
    // Operand order: a NaN (NaN ray) lands in nearT/farT and fails the final compare.
    nearT = max(nearT, min(t0, t1));
    farT = min(farT, max(t0, t1));
  }
  farT = min(farT * F4::broadcast(kConservativeFarScale), F4::broadcast(tfar));
  nearT.store(entry);
  return lessEqualMask(nearT, farT) & inside;
}

// Visits leaves near to far; leafVisitor(first, count) returns true to stop.
template <typename F4, typename LeafVisitor>
void traverseBvh4(const TriangleBvh4View& bvh, const Ray& ray, LeafVisitor&& leafVisitor) {
  if (bvh.empty()) return;
  if (Bvh4Node::isLeaf(bvh.root)) {
    leafVisitor(Bvh4Node::leafFirst(bvh.root), Bvh4Node::leafCount(bvh.root));
    return;
  }
  const Ray4Frame<F4> frame(ray);
  struct Entry {
    uint32_t child;
    float t;
  };
  Entry stack[3 * 128];
  int top = 0;
  stack[top++] = {bvh.root, ray.tnear};
  alignas(16) float entry[4];
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > ray.tfar) continue;
    uint32_t current = e.child;
    for (;;) {
      if (Bvh4Node::isLeaf(current)) {
        if (leafVisitor(Bvh4Node::leafFirst(current), Bvh4Node::leafCount(current))) return;
        break;
      }
      const Bvh4Node& node = bvh.nodes[current];
      int mask = intersectNode4(node, frame, ray.tnear, ray.tfar, entry);
      if (mask == 0) break;
      // Gather the entered children sorted by entry distance (at most four: insertion sort).
      Entry hits[4];
      int n = 0;
      while (mask) {
        const int lane = __builtin_ctz(unsigned(mask));
        mask &= mask - 1;
        if (node.child[lane] == Bvh4Node::kEmptyChild) continue;
        Entry h{node.child[lane], entry[lane]};
        int k = n++;
        while (k > 0 && hits[k - 1].t > h.t) {
          hits[k] = hits[k - 1];
          --k;
        }
        hits[k] = h;
      }
      if (n == 0) break;
      for (int k = n - 1; k >= 1; --k) stack[top++] = hits[k];
      current = hits[0].child;
    }
  }
}

template <typename F4>
bool intersectClosestBvh4Impl(const TriangleBvh4View& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh4<F4>(bvh, ray, [&](uint32_t first, uint32_t count) {
    found |= intersectLeafClosest(bvh.set, first, count, wr, ray, hit, state);
    return false;
  });
  return found;
}

template <typename F4>
bool intersectAnyBvh4Impl(const TriangleBvh4View& bvh, const Ray& ray, const QueryState& state) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh4<F4>(bvh, ray, [&](uint32_t first, uint32_t count) {
    found = intersectLeafAny(bvh.set, first, count, wr, ray, state);
    return found;
  });
  return found;
}

}  // namespace obvh
