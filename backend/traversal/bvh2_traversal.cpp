#include "traversal/bvh2_traversal.h"

#include "traversal/bvh2_traverse.h"

namespace obvh {

bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit, const QueryState& state,
                      TraversalCounters* counters) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh2(bvh.nodes, ray, counters, [&](const Bvh2Node& leaf) {
    found |= intersectLeafClosest(bvh.set, leaf.firstChildOrPrim, leaf.primCount, wr, ray, hit, state);
    return false;
  });
  return found;
}

bool intersectAny(const TriangleBvhView& bvh, const Ray& ray, const QueryState& state, TraversalCounters* counters) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh2(bvh.nodes, ray, counters, [&](const Bvh2Node& leaf) {
    found = intersectLeafAny(bvh.set, leaf.firstChildOrPrim, leaf.primCount, wr, ray, state);
    return found;
  });
  return found;
}

}  // namespace obvh
