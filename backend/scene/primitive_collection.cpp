#include "scene/primitive_collection.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "memory/huge_pages.h"
#include "scene/time_segment.h"

namespace obvh {
namespace {

bool loadVertex(const MeshDesc& mesh, uint64_t index, Vec3f& out) {
  if (index >= mesh.vertexCount) return false;
  float xyz[3];
  std::memcpy(xyz, mesh.vertices + size_t(index) * mesh.vertexStride, sizeof(xyz));
  out = {xyz[0], xyz[1], xyz[2]};
  return isValidVertex(xyz);
}

// The two triangles of a quad (v0, v1, v2, v3), split as Embree splits quads and grid cells.
void splitQuad(const Vec3f v[4], uint32_t geomID, uint32_t primID, TriangleKind first, TriangleKind second,
               StoredTriangle out[2]) {
  out[0] = {v[0], v[1], v[3], geomID, primID, first};
  out[1] = {v[2], v[3], v[1], geomID, primID, second};
}

// Fills the two triangles of quad or subdivision-cell primitive prim; returns false when the
// primitive is invalid. A subdivision cell's triangles get primID = cellBase + prim, their cell's
// index in the scene's table. (Triangle meshes: loadTriangle.)
bool loadQuad(const MeshDesc& mesh, size_t prim, uint32_t cellBase, StoredTriangle out[2]) {
  uint32_t index[4];
  std::memcpy(index, mesh.indices + prim * mesh.indexStride, sizeof(index));
  Vec3f v[4];
  for (int c = 0; c < 4; ++c)
    if (!loadVertex(mesh, index[c], v[c])) return false;
  const uint32_t primID = uint32_t(prim);
  if (mesh.topology == MeshTopology::SubdivCells) {
    splitQuad(v, mesh.geomID, cellBase + primID, TriangleKind::SubdivFirstHalf, TriangleKind::SubdivSecondHalf, out);
    return true;
  }
  splitQuad(v, mesh.geomID, primID, TriangleKind::QuadFirstHalf, TriangleKind::QuadSecondHalf, out);
  return true;
}

// The triangle of triangle-mesh primitive prim, as loadQuad loads a quad, without an early return
// per corner (one loader for three and four corners, branching on each, took about 57 instructions
// a triangle more: callgrind, bunny): the triangle is written even when invalid, and its slot
// dropped.
bool loadTriangle(const MeshDesc& mesh, size_t prim, StoredTriangle& out) {
  uint32_t index[3];
  std::memcpy(index, mesh.indices + prim * mesh.indexStride, sizeof(index));
  if ((index[0] >= mesh.vertexCount) | (index[1] >= mesh.vertexCount) | (index[2] >= mesh.vertexCount)) return false;
  float xyz[3][3];
  bool valid = true;
  for (int c = 0; c < 3; ++c) {
    std::memcpy(xyz[c], mesh.vertices + size_t(index[c]) * mesh.vertexStride, sizeof(xyz[c]));
    valid &= isValidVertex(xyz[c]);
  }
  out = {{xyz[0][0], xyz[0][1], xyz[0][2]}, {xyz[1][0], xyz[1][1], xyz[1][2]}, {xyz[2][0], xyz[2][1], xyz[2][2]},
         mesh.geomID, uint32_t(prim), TriangleKind::Triangle};
  return valid;
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

// Every primitive of the meshes gets fixed slots (one per triangle) and a grid its cells, so the
// meshes can be read in parallel; a grid's slots (two per cell) and cells start at the running
// totals of the grids before it.
struct SlotTable {
  StoredTriangles triangles;
  std::vector<unsigned char> valid;  // per slot
  std::vector<GridCell> gridCells;
  std::vector<SubdivCell> subdivCells;
};

SlotTable fillSlots(const std::vector<MeshDesc>& meshes) {
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
      slots = mesh.primCount * (mesh.topology == MeshTopology::Triangles ? 1 : 2);
    }
    slotOffset[m + 1] = slotOffset[m] + slots;
    cellOffset[m + 1] = cellOffset[m] + cells;
  }
  const size_t slotCount = slotOffset.back();

  SlotTable out;
  // Huge pages: in a virtual machine every first touch of a 4 KiB page is a costly fault (a table
  // of the dragon's triangles in 4 KiB pages took 100 of its 130 ms of collection).
  reserveWithHugePages(out.triangles, slotCount);
  out.triangles.resize(slotCount);
  out.gridCells.resize(cellOffset.back());
  out.valid.assign(slotCount, 0);
  for (const MeshDesc& mesh : meshes)
    if (mesh.topology == MeshTopology::SubdivCells)
      out.subdivCells.insert(out.subdivCells.end(), mesh.subdivCells, mesh.subdivCells + mesh.primCount);
  size_t subdivCellBase = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    const MeshDesc& mesh = meshes[m];
    if (mesh.topology == MeshTopology::Grids) {
      const std::vector<size_t>& start = gridCellStart[m];
      tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 64), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t g = r.begin(); g < r.end(); ++g) {
          const size_t cell = cellOffset[m] + start[g], slot = slotOffset[m] + 2 * start[g];
          const bool ok = loadGrid(mesh, g, uint32_t(cell), &out.triangles[slot], &out.gridCells[cell]);
          std::memset(&out.valid[slot], ok, 2 * (start[g + 1] - start[g]));
        }
      });
      continue;
    }
    if (mesh.topology == MeshTopology::Triangles) {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 4096), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t prim = r.begin(); prim < r.end(); ++prim) {
          const size_t slot = slotOffset[m] + prim;
          out.valid[slot] = loadTriangle(mesh, prim, out.triangles[slot]);
        }
      });
      continue;
    }
    const uint32_t cellBase = uint32_t(subdivCellBase);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.primCount, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t prim = r.begin(); prim < r.end(); ++prim) {
        const size_t slot = slotOffset[m] + prim * 2;
        out.valid[slot] = out.valid[slot + 1] = loadQuad(mesh, prim, cellBase, &out.triangles[slot]);
      }
    });
    if (mesh.topology == MeshTopology::SubdivCells) subdivCellBase += mesh.primCount;
  }
  return out;
}

}  // namespace

CollectedPrimitives collectPrimitives(const std::vector<MeshDesc>& meshes) {
  SlotTable slots = fillSlots(meshes);
  CollectedPrimitives out;
  out.triangles = std::move(slots.triangles);
  out.gridCells = std::move(slots.gridCells);
  out.subdivCells = std::move(slots.subdivCells);
  if (std::find(slots.valid.begin(), slots.valid.end(), 0) != slots.valid.end()) {
    // Rare (broken input): drop the invalid slots, keeping the order of the rest. The cells of a
    // dropped grid stay in the table, unreferenced, so every kept triangle's cell index holds.
    size_t kept = 0;
    for (size_t s = 0; s < out.triangles.size(); ++s)
      if (slots.valid[s]) out.triangles[kept++] = out.triangles[s];
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

CollectedMotion collectMotionPrimitives(const std::vector<MeshDesc>& meshes) {
  CollectedMotion out;
  for (const MeshDesc& mesh : meshes) {
    // The same slots at every time step; a primitive is kept when it is valid at all of them.
    const size_t steps = mesh.timeStepVertices.size();
    std::vector<SlotTable> tables(steps);
    for (size_t s = 0; s < steps; ++s) {
      MeshDesc step = mesh;
      step.vertices = mesh.timeStepVertices[s];
      tables[s] = fillSlots({step});
    }
    const uint32_t cellBase = uint32_t(out.gridCells.size()), subdivBase = uint32_t(out.subdivCells.size());
    out.gridCells.insert(out.gridCells.end(), tables[0].gridCells.begin(), tables[0].gridCells.end());
    out.subdivCells.insert(out.subdivCells.end(), tables[0].subdivCells.begin(), tables[0].subdivCells.end());
    for (size_t slot = 0; slot < tables[0].triangles.size(); ++slot) {
      bool valid = true;
      for (const SlotTable& t : tables) valid &= t.valid[slot] != 0;
      if (!valid) continue;
      const StoredTriangle& first = tables[0].triangles[slot];
      MotionTriangle tri;
      tri.geomID = first.geomID;
      tri.primID = isGridCell(first.kind)     ? cellBase + first.primID
                   : isSubdivCell(first.kind) ? subdivBase + first.primID
                                              : first.primID;
      tri.kind = first.kind;
      tri.firstVertex = uint32_t(out.vertices.size());
      tri.stepCount = uint32_t(steps);
      tri.timeStart = mesh.timeStart;
      tri.timeEnd = mesh.timeEnd;
      for (const SlotTable& t : tables) {
        const StoredTriangle& at = t.triangles[slot];
        out.vertices.insert(out.vertices.end(), {at.v0, at.v1, at.v2});
      }
      out.triangles.push_back(tri);
    }
  }
  return out;
}

bool MotionTriangle::at(const std::vector<Vec3f>& vertices, float time, StoredTriangle& out) const {
  TimeSegment s;
  if (!timeSegment(time, timeStart, timeEnd, stepCount, s)) return false;
  const float g = 1.f - s.f;
  const Vec3f* a = &vertices[firstVertex + 3 * size_t(s.segment)];
  const Vec3f* b = a + 3;
  out.v0 = a[0] * g + b[0] * s.f;
  out.v1 = a[1] * g + b[1] * s.f;
  out.v2 = a[2] * g + b[2] * s.f;
  out.geomID = geomID;
  out.primID = primID;
  out.kind = kind;
  return true;
}

Box3f MotionTriangle::bounds(const std::vector<Vec3f>& vertices) const {
  Box3f box;
  for (size_t k = 0; k < 3 * size_t(stepCount); ++k) box.extend(vertices[firstVertex + k]);
  return box;
}

}  // namespace obvh
