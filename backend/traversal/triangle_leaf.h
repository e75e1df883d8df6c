// Testing a leaf's triangles: shared by every BVH layout's traversal.
#pragma once

#include <cstdint>

#include "intersect/ray.h"
#include "intersect/triangle.h"
#include "intersect/moeller_triangle.h"
#include "intersect/watertight_triangle.h"
#include "memory/uninitialized_array.h"
#include "traversal/query_callbacks.h"

namespace obvh {

// The triangles of a scene and the per-geometry data their tests need.
struct TriangleSet {
  const StoredTriangle* triangles = nullptr;  // in leaf order
  const uint32_t* geometryMasks = nullptr;    // indexed by geomID
  const uint8_t* intersectFiltered = nullptr; // geomID has an intersection filter
  const uint8_t* occlusionFiltered = nullptr; // geomID has an occlusion filter
  const void* owner = nullptr;                // passed back to QueryCallbacks
  bool fast = false;                          // Moeller-Trumbore instead of the watertight test
  const GridCell* gridCells = nullptr;        // indexed by the primID of grid-cell triangles
  const SubdivCell* subdivCells = nullptr;    // indexed by the primID of subdivision-cell triangles
};

// The watertight test's per-ray constants (three divisions), computed when the ray first reaches a
// leaf: rays that miss every leaf never pay for them, and the fast mode's Moeller-Trumbore test
// needs none.
// The frame's storage starts uninitialized: its default member initializers were six stores at
// the start of every ray, most of which (misses) never make the frame. The fast intersector never
// reads it.
class WatertightRayOnDemand {
 public:
  [[gnu::always_inline]] const WatertightRay& of(const Ray& ray, const TriangleSet& set) {
    if (!prepared_ && !set.fast) ray_[0] = WatertightRay(ray), prepared_ = true;
    return ray_[0];
  }

 private:
  UninitializedArray<WatertightRay, 1> ray_;
  bool prepared_ = false;
};

// The watertight test's constants made by the walk once the ray is known to enter the tree
// (walkWideTree's onEntering), before any leaf reads them: the fast mode leaves them unmade.
class WatertightRayOnEntering {
 public:
  [[gnu::always_inline]] auto maker(const Ray& ray, const TriangleSet& set) {
    return [this, &ray, &set]() __attribute__((always_inline)) {
      if (!set.fast) ray_[0] = WatertightRay::withoutBranches(ray);
    };
  }
  const WatertightRay& get() const { return ray_[0]; }

 private:
  UninitializedArray<WatertightRay, 1> ray_;
};

// The same constants made at once, for walks whose rays nearly all reach a leaf (the oriented
// layouts', behind their bounds gate), where the divisions then overlap the first node tests.
[[gnu::always_inline]] inline WatertightRay watertightRayFor(const Ray& ray, const TriangleSet& set) {
  return set.fast ? WatertightRay() : WatertightRay(ray);
}

inline bool intersectTriangle(const TriangleSet& set, const WatertightRay& wr, const Ray& ray,
                              const StoredTriangle& tri, TriangleHit& th) {
  return set.fast ? intersectMoeller(ray, tri.v0, tri.v1, tri.v2, th)
                  : intersectWatertight(wr, ray, tri.v0, tri.v1, tri.v2, th);
}

// Always inlined: see makeBlockHit (triangle_block_leaf.h).
[[gnu::always_inline]] inline Hit makeTriangleHit(const TriangleSet& set, const Vec3f& v0, const Vec3f& v1,
                                                  const Vec3f& v2, uint32_t geomID, uint32_t primID, TriangleKind kind,
                                                  const TriangleHit& th, uint32_t instID) {
  Hit hit;
  hit.geomID = geomID;
  hit.primID = primID;
  hit.instID = instID;
  hit.Ng = embreeGeometryNormal(v0, v1, v2);
  // Triangles and quads, nearly every hit, with one compare: the kind tests below, as GCC compiled
  // them, took about 13 instructions a hit.
  if (kind <= TriangleKind::QuadSecondHalf) {
    const bool secondHalf = kind == TriangleKind::QuadSecondHalf;
    hit.u = secondHalf ? 1.f - th.u : th.u;
    hit.v = secondHalf ? 1.f - th.v : th.v;
    return hit;
  }
  const bool secondHalf = isSecondHalf(kind);
  hit.u = secondHalf ? 1.f - th.u : th.u;
  hit.v = secondHalf ? 1.f - th.v : th.v;
  if (isGridCell(kind)) {
    const GridCell& cell = set.gridCells[primID];
    hit.primID = cell.gridPrimID;
    hit.u = (float(cell.x) + hit.u) / float(cell.columns);
    hit.v = (float(cell.y) + hit.v) / float(cell.rows);
  } else if (isSubdivCell(kind)) {
    // The cell's (u, v) interpolated over the triangle hit, as over (v0, v1, v3) or (v2, v3, v1).
    const SubdivCell& cell = set.subdivCells[primID];
    hit.primID = cell.facePrimID;
    const int a = secondHalf ? 2 : 0, b = secondHalf ? 3 : 1, c = secondHalf ? 1 : 3;
    hit.u = cell.u[a] + th.u * (cell.u[b] - cell.u[a]) + th.v * (cell.u[c] - cell.u[a]);
    hit.v = cell.v[a] + th.u * (cell.v[b] - cell.v[a]) + th.v * (cell.v[c] - cell.v[a]);
  }
  return hit;
}

inline Hit makeTriangleHit(const TriangleSet& set, const StoredTriangle& tri, const TriangleHit& th, uint32_t instID) {
  return makeTriangleHit(set, tri.v0, tri.v1, tri.v2, tri.geomID, tri.primID, tri.kind, th, instID);
}

// The Embree primitive ID a stored triangle belongs to (a grid's, for the triangles of its cells).
inline uint32_t embreePrimID(const TriangleSet& set, const StoredTriangle& tri) {
  return isGridCell(tri.kind)     ? set.gridCells[tri.primID].gridPrimID
         : isSubdivCell(tri.kind) ? set.subdivCells[tri.primID].facePrimID
                                  : tri.primID;
}

inline bool needsFilter(const uint8_t* filtered, uint32_t geomID, const QueryState& state) {
  return state.callbacks && (state.contextFilter || (filtered && filtered[geomID]));
}

// Closest-hit test of triangles [first, first + count); shrinks ray.tfar on accepted hits.
inline bool intersectLeafClosest(const TriangleSet& set, uint32_t first, uint32_t count, const WatertightRay& wr,
                                 Ray& ray, Hit& hit, const QueryState& state) {
  bool found = false;
  for (uint32_t i = 0; i < count; ++i) {
    const StoredTriangle& tri = set.triangles[first + i];
    if ((set.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
    TriangleHit th;
    if (!intersectTriangle(set, wr, ray, tri, th)) continue;
    const Hit candidate = makeTriangleHit(set, tri, th, state.instID);
    if (needsFilter(set.intersectFiltered, tri.geomID, state) &&
        !state.callbacks->acceptHit(set.owner, ray, candidate, th.t, false))
      continue;
    ray.tfar = th.t;
    hit = candidate;
    found = true;
  }
  return found;
}

// True when any triangle of the leaf blocks the ray (and the filters accept it).
inline bool intersectLeafAny(const TriangleSet& set, uint32_t first, uint32_t count, const WatertightRay& wr,
                             const Ray& ray, const QueryState& state) {
  for (uint32_t i = 0; i < count; ++i) {
    const StoredTriangle& tri = set.triangles[first + i];
    if ((set.geometryMasks[tri.geomID] & ray.mask) == 0) continue;
    TriangleHit th;
    if (!intersectTriangle(set, wr, ray, tri, th)) continue;
    if (needsFilter(set.occlusionFiltered, tri.geomID, state) &&
        !state.callbacks->acceptHit(set.owner, ray, makeTriangleHit(set, tri, th, state.instID), th.t, true))
      continue;
    return true;
  }
  return false;
}

}  // namespace obvh
