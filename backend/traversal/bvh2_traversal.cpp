#include "traversal/bvh2_traversal.h"

#include "intersect/watertight_triangle.h"
#include "traversal/bvh2_traverse.h"

namespace obvh {
namespace {

Hit makeHit(const StoredTriangle& tri, const TriangleHit& th, uint32_t instID) {
  Hit hit;
  hit.geomID = tri.geomID;
  hit.primID = tri.primID;
  hit.instID = instID;
  hit.Ng = embreeGeometryNormal(tri.v0, tri.v1, tri.v2);
  if (tri.kind == TriangleKind::QuadSecondHalf) {
    hit.u = 1.f - th.u;
    hit.v = 1.f - th.v;
  } else {
    hit.u = th.u;
    hit.v = th.v;
  }
  return hit;
}

bool needsFilter(const uint8_t* filtered, uint32_t geomID, const QueryState& state) {
  return state.callbacks && (state.contextFilter || (filtered && filtered[geomID]));
}

}  // namespace

bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh2(bvh.nodes, ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i) {
      const StoredTriangle& tri = bvh.triangles[leaf.firstChildOrPrim + i];
      if ((bvh.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
      TriangleHit th;
      if (!intersectWatertight(wr, ray, tri.v0, tri.v1, tri.v2, th)) continue;
      const Hit candidate = makeHit(tri, th, state.instID);
      if (needsFilter(bvh.intersectFiltered, tri.geomID, state) &&
          !state.callbacks->acceptHit(bvh.owner, ray, candidate, th.t, false))
        continue;
      ray.tfar = th.t;
      hit = candidate;
      found = true;
    }
    return false;
  });
  return found;
}

bool intersectAny(const TriangleBvhView& bvh, const Ray& ray, const QueryState& state) {
  const WatertightRay wr(ray);
  bool found = false;
  traverseBvh2(bvh.nodes, ray, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i) {
      const StoredTriangle& tri = bvh.triangles[leaf.firstChildOrPrim + i];
      if ((bvh.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
      TriangleHit th;
      if (!intersectWatertight(wr, ray, tri.v0, tri.v1, tri.v2, th)) continue;
      if (needsFilter(bvh.occlusionFiltered, tri.geomID, state) &&
          !state.callbacks->acceptHit(bvh.owner, ray, makeHit(tri, th, state.instID), th.t, true))
        continue;
      found = true;
      return true;
    }
    return false;
  });
  return found;
}

}  // namespace obvh
