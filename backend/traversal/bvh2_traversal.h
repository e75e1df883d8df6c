// Scalar stack traversal of a binary BVH, nearer child first.
#pragma once

#include <vector>

#include "bvh/binary_bvh.h"
#include "intersect/ray.h"
#include "intersect/triangle.h"

namespace obvh {

// Read-only view of what traversal needs; the scene owns the data.
struct TriangleBvhView {
  const Bvh2Node* nodes = nullptr;
  const StoredTriangle* triangles = nullptr;  // in leaf order
  const uint32_t* geometryMasks = nullptr;    // indexed by geomID
  bool empty() const { return nodes == nullptr; }
};

// Closest hit in (ray.tnear, ray.tfar]; on a hit updates ray.tfar and hit and returns true.
bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit);

// Any hit in (ray.tnear, ray.tfar].
bool intersectAny(const TriangleBvhView& bvh, const Ray& ray);

}  // namespace obvh
