// A committed scene of triangle and quad meshes: collects primitives, builds the BVH, answers queries.
#pragma once

#include <vector>

#include "build/build_options.h"
#include "bvh/binary_bvh.h"
#include "intersect/ray.h"
#include "intersect/triangle.h"
#include "scene/mesh_desc.h"
#include "traversal/bvh2_traversal.h"

namespace obvh {

struct SceneStats {
  size_t primitiveCount = 0;
  size_t nodeCount = 0;
  size_t leafCount = 0;
  size_t memoryBytes = 0;
};

class TriangleScene {
 public:
  // geometryIdLimit: one more than the largest geomID in meshes.
  void build(const std::vector<MeshDesc>& meshes, uint32_t geometryIdLimit, const BuildOptions& options);

  const Box3f& bounds() const { return bounds_; }
  SceneStats stats() const;

  bool intersect(Ray& ray, Hit& hit) const { return intersectClosest(view_, ray, hit); }
  bool occluded(const Ray& ray) const { return intersectAny(view_, ray); }

 private:
  BinaryBvh bvh_;
  std::vector<StoredTriangle> triangles_;
  std::vector<uint32_t> geometryMasks_;
  Box3f bounds_;
  TriangleBvhView view_;
};

}  // namespace obvh
