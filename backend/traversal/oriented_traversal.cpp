#include "traversal/oriented_traversal.h"

#include <utility>

#include "traversal/bvh2_traverse.h"

#include "traversal/oriented_box_test.h"

namespace obvh {
namespace {

template <typename LeafVisitor>
void traverseOriented(const OrientedBvh& bvh, const Ray& ray, TraversalCounters* counters, LeafVisitor&& visit) {
  OrientedRay oriented(ray);
  const Frame* frames = bvh.frames.data();
  traverseBinaryTree(
      bvh.nodes.data(), ray, counters,
      [&](const OrientedNode& node) { return oriented.enter(node, frames, ray.tnear, ray.tfar, counters); },
      std::forward<LeafVisitor>(visit));
}

}  // namespace

bool intersectClosestOriented(const TriangleOrientedView& view, Ray& ray, Hit& hit, const QueryState& state,
                              TraversalCounters* counters) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseOriented(*view.bvh, ray, counters, [&](const OrientedNode& leaf) {
    found |= intersectLeafClosest(view.set, leaf.firstChildOrPrim, leaf.primCount, wr, ray, hit, state);
    return false;
  });
  return found;
}

bool intersectAnyOriented(const TriangleOrientedView& view, const Ray& ray, const QueryState& state,
                          TraversalCounters* counters) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseOriented(*view.bvh, ray, counters, [&](const OrientedNode& leaf) {
    found = intersectLeafAny(view.set, leaf.firstChildOrPrim, leaf.primCount, wr, ray, state);
    return found;
  });
  return found;
}

}  // namespace obvh
