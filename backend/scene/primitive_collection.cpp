#include "scene/primitive_collection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
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
  // Every primitive gets a fixed slot first, so the meshes can be read in parallel.
  std::vector<size_t> slotOffset(meshes.size() + 1, 0);
  for (size_t m = 0; m < meshes.size(); ++m)
    slotOffset[m + 1] = slotOffset[m] + meshes[m].primCount * (meshes[m].quads ? 2 : 1);
  const size_t slotCount = slotOffset.back();

  CollectedPrimitives out;
  // Huge pages: in a virtual machine every first touch of a 4 KiB page is a costly fault (a table
  // of the dragon's triangles in 4 KiB pages took 100 of its 130 ms of collection).
  reserveWithHugePages(out.triangles, slotCount);
  out.triangles.resize(slotCount);
  std::vector<unsigned char> valid(slotCount, 0);
  std::atomic<bool> anyInvalid{false};
  for (size_t m = 0; m < meshes.size(); ++m) {
    const MeshDesc& mesh = meshes[m];
    const size_t perPrim = mesh.quads ? 2 : 1;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 4096), [&](const tbb::blocked_range<size_t>& r) {
      bool invalidSeen = false;
      for (size_t prim = r.begin(); prim < r.end(); ++prim) {
        const size_t slot = slotOffset[m] + prim * perPrim;
        const bool ok = loadPrimitive(mesh, prim, &out.triangles[slot]);
        for (size_t h = 0; h < perPrim; ++h) valid[slot + h] = ok;
        invalidSeen |= !ok;
      }
      if (invalidSeen) anyInvalid.store(true, std::memory_order_relaxed);
    });
  }
  if (anyInvalid.load()) {
    // Rare (broken input): drop the invalid slots, keeping the order of the rest.
    size_t kept = 0;
    for (size_t s = 0; s < slotCount; ++s)
      if (valid[s]) out.triangles[kept++] = out.triangles[s];
    out.triangles.resize(kept);
  }

  reserveWithHugePages(out.refs, out.triangles.size());
  out.refs.resize(out.triangles.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.triangles.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const StoredTriangle& tri = out.triangles[i];
      PrimRef& ref = out.refs[i];
      ref.bounds = Box3f{};
      ref.bounds.extend(tri.v0);
      ref.bounds.extend(tri.v1);
      ref.bounds.extend(tri.v2);
      ref.index = uint32_t(i);
    }
  });
  return out;
}

}  // namespace obvh
