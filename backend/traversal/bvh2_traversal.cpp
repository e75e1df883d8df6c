#include "traversal/bvh2_traversal.h"

#include "intersect/watertight_triangle.h"
#include "traversal/box_test.h"

namespace obvh {
namespace {

constexpr int kStackSize = 128;

struct StackEntry {
  uint32_t node;
  float tEntry;
};

inline void writeHit(const StoredTriangle& tri, const TriangleHit& th, Ray& ray, Hit& hit) {
  ray.tfar = th.t;
  hit.geomID = tri.geomID;
  hit.primID = tri.primID;
  hit.Ng = embreeGeometryNormal(tri.v0, tri.v1, tri.v2);
  if (tri.kind == TriangleKind::QuadSecondHalf) {
    hit.u = 1.f - th.u;
    hit.v = 1.f - th.v;
  } else {
    hit.u = th.u;
    hit.v = th.v;
  }
}

// Visits the BVH in near-to-far order; leafVisitor returns true to stop traversal.
template <typename LeafVisitor>
void traverse(const TriangleBvhView& bvh, const Ray& ray, LeafVisitor&& leafVisitor) {
  if (bvh.empty()) return;
  const BoxRay boxRay(ray);
  StackEntry stack[kStackSize];
  int top = 0;
  const Bvh2Node* nodes = bvh.nodes;
  if (intersectBox(boxRay, nodes[0].bounds, ray.tnear, ray.tfar) == std::numeric_limits<float>::infinity())
    return;
  stack[top++] = {0, ray.tnear};
  while (top > 0) {
    const StackEntry entry = stack[--top];
    if (entry.tEntry > ray.tfar) continue;
    uint32_t current = entry.node;
    for (;;) {
      const Bvh2Node& node = nodes[current];
      if (node.isLeaf()) {
        if (leafVisitor(node)) return;
        break;
      }
      const uint32_t left = node.firstChildOrPrim, right = left + 1;
      const float tl = intersectBox(boxRay, nodes[left].bounds, ray.tnear, ray.tfar);
      const float tr = intersectBox(boxRay, nodes[right].bounds, ray.tnear, ray.tfar);
      const bool hitLeft = tl != std::numeric_limits<float>::infinity();
      const bool hitRight = tr != std::numeric_limits<float>::infinity();
      if (hitLeft && hitRight) {
        const bool leftFirst = tl <= tr;
        // A degenerate tree deeper than the stack can only come from a broken builder.
        if (top < kStackSize) stack[top++] = {leftFirst ? right : left, leftFirst ? tr : tl};
        current = leftFirst ? left : right;
      } else if (hitLeft) {
        current = left;
      } else if (hitRight) {
        current = right;
      } else {
        break;
      }
    }
  }
}

}  // namespace

bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit) {
  const WatertightRay wr(ray);
  bool found = false;
  traverse(bvh, ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i) {
      const StoredTriangle& tri = bvh.triangles[leaf.firstChildOrPrim + i];
      if ((bvh.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
      TriangleHit th;
      if (intersectWatertight(wr, ray, tri.v0, tri.v1, tri.v2, th)) {
        writeHit(tri, th, ray, hit);
        found = true;
      }
    }
    return false;
  });
  return found;
}

bool intersectAny(const TriangleBvhView& bvh, const Ray& ray) {
  const WatertightRay wr(ray);
  bool found = false;
  traverse(bvh, ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i) {
      const StoredTriangle& tri = bvh.triangles[leaf.firstChildOrPrim + i];
      if ((bvh.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
      TriangleHit th;
      if (intersectWatertight(wr, ray, tri.v0, tri.v1, tri.v2, th)) {
        found = true;
        return true;
      }
    }
    return false;
  });
  return found;
}

}  // namespace obvh
