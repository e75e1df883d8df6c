#include "scene/primitive_collection.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>

#include "memory/huge_pages.h"

namespace obvh {
namespace {

bool isValidCoordinate(float c) { return std::isfinite(c) && std::fabs(c) < kLargestValidCoordinate; }

bool loadVertex(const MeshDesc& mesh, uint32_t index, Vec3f& out) {
  if (index >= mesh.vertexCount) return false;
  float xyz[3];
  std::memcpy(xyz, mesh.vertices + size_t(index) * mesh.vertexStride, sizeof(xyz));
  out = {xyz[0], xyz[1], xyz[2]};
  return isValidCoordinate(xyz[0]) && isValidCoordinate(xyz[1]) && isValidCoordinate(xyz[2]);
}

// Fills the one or two triangles of primitive prim; returns false when the primitive is invalid.
bool loadPrimitive(const MeshDesc& mesh, size_t prim, StoredTriangle out[2]) {
  const int cornerCount = mesh.quads ? 4 : 3;
  uint32_t index[4];
  std::memcpy(index, mesh.indices + prim * mesh.indexStride, sizeof(uint32_t) * cornerCount);
  Vec3f v[4];
  for (int c = 0; c < cornerCount; ++c)
    if (!loadVertex(mesh, index[c], v[c])) return false;
  const uint32_t primID = uint32_t(prim);
  if (!mesh.quads) {
    out[0] = {v[0], v[1], v[2], mesh.geomID, primID, TriangleKind::Triangle};
    return true;
  }
  out[0] = {v[0], v[1], v[3], mesh.geomID, primID, TriangleKind::QuadFirstHalf};
  out[1] = {v[2], v[3], v[1], mesh.geomID, primID, TriangleKind::QuadSecondHalf};
  return true;
}

}  // namespace

CollectedPrimitives collectPrimitives(const std::vector<MeshDesc>& meshes) {
  // Every primitive gets fixed slots first, so the meshes can be read in parallel.
  std::vector<size_t> slotOffset(meshes.size() + 1, 0);
  for (size_t m = 0; m < meshes.size(); ++m)
    slotOffset[m + 1] = slotOffset[m] + meshes[m].primCount * (meshes[m].quads ? 2 : 1);
  const size_t slotCount = slotOffset.back();

  std::vector<StoredTriangle> slots(slotCount);
  std::vector<unsigned char> valid(slotCount, 0);
  for (size_t m = 0; m < meshes.size(); ++m) {
    const MeshDesc& mesh = meshes[m];
    const size_t perPrim = mesh.quads ? 2 : 1;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t prim = r.begin(); prim < r.end(); ++prim) {
        const size_t slot = slotOffset[m] + prim * perPrim;
        const bool ok = loadPrimitive(mesh, prim, &slots[slot]);
        for (size_t h = 0; h < perPrim; ++h) valid[slot + h] = ok;
      }
    });
  }

  CollectedPrimitives out;
  reserveWithHugePages(out.triangles, slotCount);
  reserveWithHugePages(out.refs, slotCount);
  for (size_t s = 0; s < slotCount; ++s) {
    if (!valid[s]) continue;
    const StoredTriangle& tri = slots[s];
    PrimRef ref;
    ref.bounds.extend(tri.v0);
    ref.bounds.extend(tri.v1);
    ref.bounds.extend(tri.v2);
    ref.index = uint32_t(out.triangles.size());
    out.triangles.push_back(tri);
    out.refs.push_back(ref);
  }
  return out;
}

}  // namespace obvh
