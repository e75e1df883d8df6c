// Ray queries against the triangle BVH of one scene.
#pragma once

#include <cstdint>

#include "bvh/binary_bvh.h"
#include "intersect/ray.h"
#include "intersect/triangle.h"
#include "traversal/query_callbacks.h"

namespace obvh {

// Read-only view of what traversal needs; the scene owns the data.
struct TriangleBvhView {
  const Bvh2Node* nodes = nullptr;
  const StoredTriangle* triangles = nullptr;     // in leaf order
  const uint32_t* geometryMasks = nullptr;       // indexed by geomID
  const uint8_t* intersectFiltered = nullptr;    // geomID has an intersection filter
  const uint8_t* occlusionFiltered = nullptr;    // geomID has an occlusion filter
  const void* owner = nullptr;                   // passed back to QueryCallbacks
  bool empty() const { return nodes == nullptr; }
};

// Closest hit in (ray.tnear, ray.tfar]; on a hit updates ray.tfar and hit and returns true.
bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit, const QueryState& state);

// Any hit in (ray.tnear, ray.tfar] that the filters accept.
bool intersectAny(const TriangleBvhView& bvh, const Ray& ray, const QueryState& state);

}  // namespace obvh
