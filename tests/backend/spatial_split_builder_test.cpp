// The spatial-split builder (RTC_BUILD_QUALITY_HIGH): a triangle split between leaves is never
// lost (every point of it lies in the box of a leaf that references it), the reference budget
// holds, boxes nest, the tree does not depend on the thread count, and rays find the same hits
// as through the binned-SAH tree.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <limits>
#include <random>

#include "builders/binned_sah_builder.h"
#include "builders/spatial_split_builder.h"
#include "scene/primitive_collection.h"
#include "traversal/bvh2_traversal.h"
#include "backend_mesh_desc.h"
#include "stack_generator.h"
#include "test_scenes.h"

namespace obvh {
namespace {

// Long slanted lines over slabs (where spatial splits pay) plus a random soup.
CollectedPrimitives slantedScene() {
  const tools::StackPreset* preset = tools::findStackPreset("diagonal-42k");
  const tools::StackScene stack = tools::generateStack(preset->params, preset->name);
  std::vector<tools::MeshData> data = stack.groups;
  data.push_back(test::randomTriangleSoup(20000, 5));
  std::vector<MeshDesc> meshes;  // point into `data`, which outlives the collection (it copies the triangles)
  for (size_t g = 0; g < data.size(); ++g) meshes.push_back(tools::backendMeshDesc(data[g], uint32_t(g)));
  return collectPrimitives(meshes);
}

void collectLeaves(const BinaryBvh& bvh, std::vector<std::vector<uint32_t>>& leavesOfPrim) {
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
    const Bvh2Node& node = bvh.nodes[n];
    if (!node.isLeaf()) continue;
    for (uint32_t i = 0; i < node.primCount; ++i) leavesOfPrim[bvh.primIndices[node.firstChildOrPrim + i]].push_back(n);
  }
}

bool inside(const Box3f& box, const Vec3f& p) {
  // The clipped boxes are computed in float: allow a few ulps of the scene's scale.
  const float eps = 1e-5f * std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z), 1.f});
  return p.x >= box.lower.x - eps && p.y >= box.lower.y - eps && p.z >= box.lower.z - eps &&
         p.x <= box.upper.x + eps && p.y <= box.upper.y + eps && p.z <= box.upper.z + eps;
}

// A budget of 2% runs out high in the tree, so the splits below fall back to object splits or
// have their duplicates refused (the paths that keep each subtree inside its slots).
class SpatialSplitBudget : public ::testing::TestWithParam<float> {};

TEST_P(SpatialSplitBudget, NoTriangleIsLostAndTheBudgetHolds) {
  const CollectedPrimitives collected = slantedScene();
  BuildOptions options;
  options.leafBlockSize = 4;
  SpatialSplitSettings settings;
  settings.referenceBudget = GetParam();
  const BinaryBvh bvh = buildSpatialSah(collected.refs, collected.triangles.data(), options, settings);
  const size_t n = collected.triangles.size();
  std::printf("[sbvh] %zu triangles, %zu references (%.1f%% extra), %zu nodes\n", n, bvh.primIndices.size(),
              100.0 * double(bvh.primIndices.size() - n) / double(n), bvh.nodes.size());
  EXPECT_GT(bvh.primIndices.size(), n) << "no spatial split happened on slanted lines";
  EXPECT_LE(bvh.primIndices.size(), n + size_t(settings.referenceBudget * double(n)));

  std::vector<std::vector<uint32_t>> leavesOfPrim(n);
  collectLeaves(bvh, leavesOfPrim);
  // Points on each triangle (vertices, edge points, interior) lie in some leaf box referencing it.
  size_t lost = 0;
  for (uint32_t prim = 0; prim < n; ++prim) {
    ASSERT_FALSE(leavesOfPrim[prim].empty()) << "triangle " << prim << " is in no leaf";
    const StoredTriangle& t = collected.triangles[prim];
    for (int i = 0; i <= 6; ++i)
      for (int j = 0; i + j <= 6; ++j) {
        const float u = float(i) / 6.f, v = float(j) / 6.f;
        const Vec3f p = t.v0 * (1.f - u - v) + t.v1 * u + t.v2 * v;
        bool covered = false;
        for (uint32_t leaf : leavesOfPrim[prim]) covered = covered || inside(bvh.nodes[leaf].bounds, p);
        lost += !covered;
      }
  }
  EXPECT_EQ(lost, 0u);
  // Children's boxes lie within their parent's.
  for (const Bvh2Node& node : bvh.nodes) {
    if (node.isLeaf()) continue;
    for (uint32_t c = node.firstChildOrPrim; c < node.firstChildOrPrim + 2; ++c) {
      EXPECT_TRUE(inside(node.bounds, bvh.nodes[c].bounds.lower));
      EXPECT_TRUE(inside(node.bounds, bvh.nodes[c].bounds.upper));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SpatialSplitBuilder, SpatialSplitBudget, ::testing::Values(1.0f, 0.02f));

TEST(SpatialSplitBuilder, SameTreeOnOneAndTwoThreads) {
  const CollectedPrimitives collected = slantedScene();
  const BuildOptions options;
  const auto build = [&](int threads) {
    tbb::task_arena arena(threads);
    return arena.execute([&] { return buildSpatialSah(collected.refs, collected.triangles.data(), options); });
  };
  const BinaryBvh one = build(1), two = build(2);
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  ASSERT_EQ(one.primIndices, two.primIndices);
  for (size_t i = 0; i < one.nodes.size(); ++i) {
    ASSERT_EQ(one.nodes[i].firstChildOrPrim, two.nodes[i].firstChildOrPrim);
    ASSERT_EQ(one.nodes[i].bounds.lower.y, two.nodes[i].bounds.lower.y);
    ASSERT_EQ(one.nodes[i].bounds.upper.x, two.nodes[i].bounds.upper.x);
  }
}

TEST(SpatialSplitBuilder, RaysFindTheSameHitsAsThroughTheBinnedTree) {
  const CollectedPrimitives collected = slantedScene();
  const BuildOptions options;
  PrimRefs refs = collected.refs;
  const BinaryBvh binned = buildBinnedSah(refs, options);
  const BinaryBvh spatial = buildSpatialSah(collected.refs, collected.triangles.data(), options);
  const auto leafTriangles = [&](const BinaryBvh& bvh) {
    StoredTriangles out;
    for (uint32_t index : bvh.primIndices) out.push_back(collected.triangles[index]);
    return out;
  };
  const StoredTriangles binnedTriangles = leafTriangles(binned), spatialTriangles = leafTriangles(spatial);
  const std::vector<uint32_t> masks(64, 0xFFFFFFFFu);
  const TriangleBvhView a{binned.nodes.data(), {binnedTriangles.data(), masks.data(), nullptr, nullptr, nullptr, false}};
  const TriangleBvhView b{spatial.nodes.data(), {spatialTriangles.data(), masks.data(), nullptr, nullptr, nullptr, false}};
  Box3f bounds;
  for (const PrimRef& r : collected.refs) bounds.extend(r.bounds);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const QueryState state;
  size_t hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    const Vec3f extent = bounds.upper - bounds.lower;
    const Vec3f from = bounds.lower + Vec3f{unit(rng) * extent.x, unit(rng) * extent.y, unit(rng) * extent.z} * 1.2f - extent * 0.1f;
    const Vec3f to = bounds.lower + Vec3f{unit(rng) * extent.x, unit(rng) * extent.y, unit(rng) * extent.z};
    ray.org = from;
    ray.dir = to - from;
    ray.tfar = std::numeric_limits<float>::infinity();
    Ray ra = ray, rb = ray;
    Hit ha, hb;
    const bool fa = intersectClosest(a, ra, ha, state), fb = intersectClosest(b, rb, hb, state);
    ASSERT_EQ(fa, fb) << "ray " << i;
    EXPECT_EQ(ra.tfar, rb.tfar) << "ray " << i;
    EXPECT_EQ(intersectAny(a, ray, state), intersectAny(b, ray, state));
    hits += fa;
  }
  EXPECT_GT(hits, 5000u);
}

}  // namespace
}  // namespace obvh
