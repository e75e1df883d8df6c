#include "scene/triangle_scene.h"

#include <tbb/parallel_for.h>

#include "build/binned_sah_builder.h"
#include "scene/primitive_collection.h"

namespace obvh {

void TriangleScene::build(const std::vector<MeshDesc>& meshes, uint32_t geometryIdLimit,
                          const BuildOptions& options) {
  geometryMasks_.assign(geometryIdLimit, 0u);
  for (const MeshDesc& mesh : meshes) geometryMasks_[mesh.geomID] = mesh.mask;

  CollectedPrimitives collected = collectPrimitives(meshes);
  bvh_ = buildBinnedSah(collected.refs, options);

  // Store triangles in leaf order so a leaf reads one contiguous range.
  triangles_.resize(bvh_.primIndices.size());
  tbb::parallel_for(size_t(0), triangles_.size(), [&](size_t i) {
    triangles_[i] = collected.triangles[bvh_.primIndices[i]];
  });

  bounds_ = bvh_.empty() ? Box3f{} : bvh_.nodes[0].bounds;
  view_ = TriangleBvhView{};
  if (!bvh_.empty()) view_ = {bvh_.nodes.data(), triangles_.data(), geometryMasks_.data()};
}

SceneStats TriangleScene::stats() const {
  SceneStats s;
  s.primitiveCount = triangles_.size();
  s.nodeCount = bvh_.nodes.size();
  for (const Bvh2Node& node : bvh_.nodes) s.leafCount += node.isLeaf() ? 1 : 0;
  s.memoryBytes = bvh_.nodes.size() * sizeof(Bvh2Node) + triangles_.size() * sizeof(StoredTriangle) +
                  geometryMasks_.size() * sizeof(uint32_t);
  return s;
}

}  // namespace obvh
