// Grid meshes in the backend: the cells a grid contributes, which grids are skipped, and the hit a
// grid cell reports (the grid's primID and (u, v) across the grid), with every layout agreeing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "backend_mesh_desc.h"
#include "scene/primitive_collection.h"
#include "scene/scene_accel.h"
#include "test_scenes.h"

namespace obvh {
namespace {

// A flat 4 x 3 vertex field at z = 0, x = column, y = row.
test::MeshData flatField() {
  test::MeshData mesh;
  mesh.grid = true;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) mesh.vertices.insert(mesh.vertices.end(), {float(x), float(y), 0.f});
  return mesh;
}

TEST(GridCollection, CellsAndSkippedGrids) {
  test::MeshData mesh = flatField();
  mesh.grids = {
      {0, 4, 4, 3},  // the whole field: 3 x 2 cells
      {5, 4, 2, 2},  // one cell in the middle
      {0, 4, 1, 3},  // one column: no cells
      {0, 4, 4, 1},  // one row: no cells
      {8, 4, 4, 2},  // its second row lies past the vertex buffer: skipped whole
  };
  const CollectedPrimitives c = collectPrimitives({tools::backendMeshDesc(mesh, 7)});
  ASSERT_EQ(c.triangles.size(), 2u * (6 + 1));
  for (const StoredTriangle& tri : c.triangles) {
    EXPECT_EQ(tri.geomID, 7u);
    EXPECT_TRUE(isGridCell(tri.kind));
    const GridCell& cell = c.gridCells.at(tri.primID);
    EXPECT_LE(cell.gridPrimID, 1u);
    // The first half spans the cell's (x, y), (x + 1, y) and (x, y + 1) corners.
    if (tri.kind == TriangleKind::GridFirstHalf) {
      const uint32_t x0 = cell.gridPrimID == 0 ? 0 : 1, y0 = cell.gridPrimID == 0 ? 0 : 1;
      EXPECT_EQ(tri.v0.x, float(x0 + cell.x));
      EXPECT_EQ(tri.v0.y, float(y0 + cell.y));
      EXPECT_EQ(tri.v1.x, float(x0 + cell.x + 1));
      EXPECT_EQ(tri.v2.y, float(y0 + cell.y + 1));
    }
  }
  const GridCell& last = c.gridCells.at(c.triangles[11].primID);
  EXPECT_EQ(last.gridPrimID, 0u);
  EXPECT_EQ(last.x, 2u);
  EXPECT_EQ(last.y, 1u);
  EXPECT_EQ(last.columns, 3u);
  EXPECT_EQ(last.rows, 2u);
}

TEST(GridCollection, InvalidVertexSkipsTheWholeGrid) {
  test::MeshData mesh = flatField();
  mesh.grids = {{0, 4, 4, 3}, {0, 4, 2, 2}};
  mesh.vertices[3 * 10 + 2] = std::numeric_limits<float>::quiet_NaN();  // inside the first grid only
  const CollectedPrimitives c = collectPrimitives({tools::backendMeshDesc(mesh, 0)});
  ASSERT_EQ(c.triangles.size(), 2u);
  EXPECT_EQ(c.gridCells.at(c.triangles[0].primID).gridPrimID, 1u);
}

// A ray down onto the field's cell (2, 1) at (2.25, 1.5): grid primID, (u, v) = (2.25 / 3, 1.5 / 2).
TEST(GridCollection, HitsReportTheGridAndItsUv) {
  test::MeshData mesh = flatField();
  mesh.grids = {{0, 4, 4, 3}};
  for (const char* layout : {"bvh2", "bvh4", "bvh8", "obb", "hybrid"}) {
    SceneDesc desc;
    desc.meshes = {tools::backendMeshDesc(mesh, 0)};
    desc.geometryIdLimit = 1;
    BuildOptions options;
    options.layout = std::string(layout) == "bvh2"   ? AccelLayout::Bvh2
                     : std::string(layout) == "bvh4" ? AccelLayout::Bvh4
                     : std::string(layout) == "bvh8" ? AccelLayout::Bvh8
                     : std::string(layout) == "obb"  ? AccelLayout::Obb
                                                     : AccelLayout::Hybrid;
    SceneAccel accel;
    accel.build(desc, options);
    for (const float x : {2.25f, 2.75f}) {  // both halves of the cell
      Ray ray;
      ray.org = {x, 1.5f + (x - 2.f) * 0.2f, 1.f};
      ray.dir = {0.f, 0.f, -1.f};
      ray.tnear = 0.f;
      ray.tfar = std::numeric_limits<float>::infinity();
      Hit hit;
      ASSERT_TRUE(accel.intersect(ray, hit, QueryState{})) << layout;
      EXPECT_EQ(hit.primID, 0u) << layout;
      EXPECT_NEAR(hit.u, x / 3.f, 1e-6f) << layout;
      EXPECT_NEAR(hit.v, ray.org.y / 2.f, 1e-6f) << layout;
      EXPECT_FLOAT_EQ(ray.tfar, 1.f) << layout;
    }
  }
}

}  // namespace
}  // namespace obvh
