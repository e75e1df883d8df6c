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

bool loadVertex(const MeshDesc& mesh, uint64_t index, Vec3f& out) {
  if (index >= mesh.vertexCount) return false;
  float xyz[3];
  std::memcpy(xyz, mesh.vertices + size_t(index) * mesh.vertexStride, sizeof(xyz));
  out = {xyz[0], xyz[1], xyz[2]};
  return isValidCoordinate(xyz[0]) && isValidCoordinate(xyz[1]) && isValidCoordinate(xyz[2]);
}

// The two triangles of a quad (v0, v1, v2, v3), split as Embree splits quads and grid cells.
void splitQuad(const Vec3f v[4], uint32_t geomID, uint32_t primID, TriangleKind first, TriangleKind second,
               StoredTriangle out[2]) {
  out[0] = {v[0], v[1], v[3], geomID, primID, first};
  out[1] = {v[2], v[3], v[1], geomID, primID, second};
}

// Fills the one or two triangles of primitive prim; returns false when the primitive is invalid.
bool loadPrimitive(const MeshDesc& mesh, size_t prim, StoredTriangle out[2]) {
  const bool quads = mesh.topology == MeshTopology::Quads;
  const int cornerCount = quads ? 4 : 3;
  uint32_t index[4];
  std::memcpy(index, mesh.indices + prim * mesh.indexStride, sizeof(uint32_t) * cornerCount);
  Vec3f v[4];
  for (int c = 0; c < cornerCount; ++c)
    if (!loadVertex(mesh, index[c], v[c])) return false;
  const uint32_t primID = uint32_t(prim);
  if (!quads) {
    out[0] = {v[0], v[1], v[2], mesh.geomID, primID, TriangleKind::Triangle};
    return true;
  }
  splitQuad(v, mesh.geomID, primID, TriangleKind::QuadFirstHalf, TriangleKind::QuadSecondHalf, out);
  return true;
}

// Embree's RTCGrid, read field by field (the buffer need not be aligned for the struct).
struct GridRecord {
  uint32_t startVertexID = 0, stride = 0;
  uint16_t width = 0, height = 0;
  size_t cellCount() const { return width < 2 || height < 2 ? 0 : size_t(width - 1) * size_t(height - 1); }
  uint64_t vertexIndex(uint32_t x, uint32_t y) const { return uint64_t(startVertexID) + uint64_t(y) * stride + x; }
};

GridRecord gridRecord(const MeshDesc& mesh, size_t prim) {
  const unsigned char* p = mesh.indices + prim * mesh.indexStride;
  GridRecord g;
  std::memcpy(&g.startVertexID, p, 4);
  std::memcpy(&g.stride, p + 4, 4);
  std::memcpy(&g.width, p + 8, 2);
  std::memcpy(&g.height, p + 10, 2);
  return g;
}

// Writes the triangles and cells of grid prim at triangles[0, 2 * cells) and cells[0, cells);
// false when one of the grid's vertices is missing or invalid.
bool loadGrid(const MeshDesc& mesh, size_t prim, uint32_t firstCell, StoredTriangle* triangles, GridCell* cells) {
  const GridRecord g = gridRecord(mesh, prim);
  if (g.cellCount() == 0) return true;
  Vec3f unused;
  for (uint32_t y = 0; y < g.height; ++y)
    for (uint32_t x = 0; x < g.width; ++x)
      if (!loadVertex(mesh, g.vertexIndex(x, y), unused)) return false;
  const uint32_t columns = g.width - 1u, rows = g.height - 1u;
  for (uint32_t y = 0; y < rows; ++y) {
    for (uint32_t x = 0; x < columns; ++x) {
      const size_t local = size_t(y) * columns + x;
      Vec3f v[4];
      loadVertex(mesh, g.vertexIndex(x, y), v[0]);
      loadVertex(mesh, g.vertexIndex(x + 1, y), v[1]);
      loadVertex(mesh, g.vertexIndex(x + 1, y + 1), v[2]);
      loadVertex(mesh, g.vertexIndex(x, y + 1), v[3]);
      splitQuad(v, mesh.geomID, firstCell + uint32_t(local), TriangleKind::GridFirstHalf,
                TriangleKind::GridSecondHalf, &triangles[2 * local]);
      cells[local] = {uint32_t(prim), uint16_t(x), uint16_t(y), uint16_t(columns), uint16_t(rows)};
    }
  }
  return true;
}

}  // namespace

CollectedPrimitives collectPrimitives(const std::vector<MeshDesc>& meshes) {
  // Every primitive gets a fixed slot first, so the meshes can be read in parallel. A grid's slots
  // (two per cell) and cells start at the running totals of the grids before it.
  std::vector<size_t> slotOffset(meshes.size() + 1, 0);
  std::vector<std::vector<size_t>> gridCellStart(meshes.size());  // per grid, within its mesh
  std::vector<size_t> cellOffset(meshes.size() + 1, 0);
  for (size_t m = 0; m < meshes.size(); ++m) {
    const MeshDesc& mesh = meshes[m];
    size_t slots = 0, cells = 0;
    if (mesh.topology == MeshTopology::Grids) {
      gridCellStart[m].resize(mesh.primCount + 1, 0);
      for (size_t g = 0; g < mesh.primCount; ++g) gridCellStart[m][g + 1] = gridCellStart[m][g] + gridRecord(mesh, g).cellCount();
      cells = gridCellStart[m].back();
      slots = 2 * cells;
    } else {
      slots = mesh.primCount * (mesh.topology == MeshTopology::Quads ? 2 : 1);
    }
    slotOffset[m + 1] = slotOffset[m] + slots;
    cellOffset[m + 1] = cellOffset[m] + cells;
  }
  const size_t slotCount = slotOffset.back();

  CollectedPrimitives out;
  // Huge pages: in a virtual machine every first touch of a 4 KiB page is a costly fault (a table
  // of the dragon's triangles in 4 KiB pages took 100 of its 130 ms of collection).
  reserveWithHugePages(out.triangles, slotCount);
  out.triangles.resize(slotCount);
  out.gridCells.resize(cellOffset.back());
  std::vector<unsigned char> valid(slotCount, 0);
  std::atomic<bool> anyInvalid{false};
  for (size_t m = 0; m < meshes.size(); ++m) {
    const MeshDesc& mesh = meshes[m];
    if (mesh.topology == MeshTopology::Grids) {
      const std::vector<size_t>& start = gridCellStart[m];
      tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 64), [&](const tbb::blocked_range<size_t>& r) {
        bool invalidSeen = false;
        for (size_t g = r.begin(); g < r.end(); ++g) {
          const size_t cell = cellOffset[m] + start[g], slot = slotOffset[m] + 2 * start[g];
          const bool ok = loadGrid(mesh, g, uint32_t(cell), &out.triangles[slot], &out.gridCells[cell]);
          std::memset(&valid[slot], ok, 2 * (start[g + 1] - start[g]));
          invalidSeen |= !ok;
        }
        if (invalidSeen) anyInvalid.store(true, std::memory_order_relaxed);
      });
      continue;
    }
    const size_t perPrim = mesh.topology == MeshTopology::Quads ? 2 : 1;
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
    // Rare (broken input): drop the invalid slots, keeping the order of the rest. The cells of a
    // dropped grid stay in the table, unreferenced, so every kept triangle's cell index holds.
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
