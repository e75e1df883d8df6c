// The same input gives the same tree and the same hits whatever the number of build threads.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>

#include "builders/binned_sah_builder.h"
#include "builders/distance_sah_builder.h"
#include "builders/kmeans_builder.h"
#include "builders/morton_builder.h"
#include "builders/obb_split_builder.h"
#include "bvh/wide_bvh.h"
#include "scene/primitive_collection.h"
#include "scene/scene_accel.h"
#include "backend_mesh_desc.h"
#include "test_scenes.h"

namespace obvh {
namespace {

// Large enough for the parallel binning (2^16 primitives) and parallel recursion paths.
test::MeshData bigSoup() { return test::randomTriangleSoup(150000, 31); }

template <typename F>
auto withThreads(int threads, F&& f) {
  tbb::task_arena arena(threads);
  return arena.execute(f);
}

// Node indices come from an atomic counter and depend on task timing; the tree does not.
void expectSameTree(const BinaryBvh& a, uint32_t ia, const BinaryBvh& b, uint32_t ib) {
  const Bvh2Node& na = a.nodes[ia];
  const Bvh2Node& nb = b.nodes[ib];
  ASSERT_EQ(na.primCount, nb.primCount);
  ASSERT_EQ(na.bounds.lower.x, nb.bounds.lower.x);
  ASSERT_EQ(na.bounds.upper.z, nb.bounds.upper.z);
  if (na.isLeaf()) {
    for (uint32_t i = 0; i < na.primCount; ++i)
      ASSERT_EQ(a.primIndices[na.firstChildOrPrim + i], b.primIndices[nb.firstChildOrPrim + i]);
    return;
  }
  expectSameTree(a, na.firstChildOrPrim, b, nb.firstChildOrPrim);
  expectSameTree(a, na.firstChildOrPrim + 1, b, nb.firstChildOrPrim + 1);
}

TEST(BuildDeterminism, BinnedSahTreeIsTheSameOnOneAndTwoThreads) {
  const test::MeshData soup = bigSoup();
  const CollectedPrimitives collected = collectPrimitives({tools::backendMeshDesc(soup)});
  const BuildOptions options;
  const BinaryBvh one = withThreads(1, [&] {
    PrimRefs refs = collected.refs;
    return buildBinnedSah(refs, options);
  });
  const BinaryBvh two = withThreads(2, [&] {
    PrimRefs refs = collected.refs;
    return buildBinnedSah(refs, options);
  });
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  expectSameTree(one, 0, two, 0);
}

// RTC_BUILD_QUALITY_LOW: the Morton-code tree, with every triangle in exactly one leaf.
TEST(BuildDeterminism, MortonTreeIsTheSameOnOneAndTwoThreads) {
  const test::MeshData soup = bigSoup();
  const CollectedPrimitives collected = collectPrimitives({tools::backendMeshDesc(soup)});
  BuildOptions options;
  options.maxLeafSize = 4;
  const auto build = [&](int threads) {
    return withThreads(threads, [&] {
      PrimRefs refs = collected.refs;
      return buildMorton(refs, options);
    });
  };
  const BinaryBvh one = build(1), two = build(2);
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  expectSameTree(one, 0, two, 0);
  std::vector<int> seen(collected.refs.size(), 0);
  for (uint32_t index : one.primIndices) ++seen[index];
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(seen.size()));
  for (const Bvh2Node& node : one.nodes) {
    if (node.isLeaf()) {
      EXPECT_LE(node.primCount, 4u);
      for (uint32_t i = 0; i < node.primCount; ++i) {
        const Box3f& b = collected.refs[one.primIndices[node.firstChildOrPrim + i]].bounds;
        EXPECT_TRUE(node.bounds.lower.x <= b.lower.x && node.bounds.upper.y >= b.upper.y);
      }
    }
  }
}

// The alternative builders (builder=kmeans, builder=distance) sum floating-point centroids in
// parallel: their reductions run in a fixed order, so the trees still match.
TEST(BuildDeterminism, KMeansAndDistanceTreesAreTheSameOnOneAndTwoThreads) {
  const test::MeshData soup = bigSoup();
  const CollectedPrimitives collected = collectPrimitives({tools::backendMeshDesc(soup)});
  BuildOptions options;
  options.distanceAlpha = 0.3f;
  options.distanceSource = {0.2f, 0.7f, 0.4f};
  for (auto builder : {buildKMeans, buildDistanceSah}) {
    const auto build = [&](int threads) {
      return withThreads(threads, [&] {
        PrimRefs refs = collected.refs;
        return builder(refs, options);
      });
    };
    const BinaryBvh one = build(1), two = build(2);
    ASSERT_EQ(one.nodes.size(), two.nodes.size());
    expectSameTree(one, 0, two, 0);
  }
}

TEST(BuildDeterminism, ObbFrameTreeIsTheSameOnOneAndTwoThreads) {
  const test::MeshData soup = bigSoup();
  const CollectedPrimitives collected = collectPrimitives({tools::backendMeshDesc(soup)});
  const BuildOptions options;
  const BinaryBvh one = withThreads(1, [&] {
    PrimRefs refs = collected.refs;
    return buildInObbFrames(refs, collected.triangles.data(), options);
  });
  const BinaryBvh two = withThreads(2, [&] {
    PrimRefs refs = collected.refs;
    return buildInObbFrames(refs, collected.triangles.data(), options);
  });
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  expectSameTree(one, 0, two, 0);
}

// The SAH collapse plans and writes subtrees in parallel at positions computed beforehand: the
// wide tree must come out byte for byte the same (node order, block order, NaN padding included).
// The layout an appending writer gives: each node before its children's subtrees, lanes in order,
// blocks in the order the leaves are reached; every node and block used exactly once.
template <int N>
void expectDepthFirstLayout(const WideBvh<N>& bvh, uint32_t code, uint32_t& nextNode, uint32_t& nextBlock) {
  using Node = WideNode<N>;
  if (code == Node::kEmptyChild) return;
  if (Node::isLeaf(code)) {
    ASSERT_EQ(Node::leafFirstBlock(code), nextBlock);
    nextBlock += Node::leafBlockCount(code);
    return;
  }
  ASSERT_EQ(code, nextNode);
  ++nextNode;
  for (int lane = 0; lane < N; ++lane) expectDepthFirstLayout(bvh, bvh.nodes[code].child[lane], nextNode, nextBlock);
}

template <int N>
void expectSameWideTreeOnOneAndTwoThreads() {
  const test::MeshData soup = bigSoup();
  CollectedPrimitives collected = collectPrimitives({tools::backendMeshDesc(soup)});
  BuildOptions options;
  options.maxLeafSize = 16;
  const BinaryBvh binary = buildBinnedSah(collected.refs, options);
  StoredTriangles inLeafOrder;
  for (uint32_t prim : binary.primIndices) inLeafOrder.push_back(collected.triangles[prim]);
  CollapseOptions collapse;
  collapse.method = CollapseMethod::SahOptimal;
  collapse.maxLeafPrims = 16;
  const WideBvh<N> one = withThreads(1, [&] { return collapseToWide<N>(binary, inLeafOrder.data(), collapse); });
  const WideBvh<N> two = withThreads(2, [&] { return collapseToWide<N>(binary, inLeafOrder.data(), collapse); });
  ASSERT_GT(one.nodes.size(), 1000u);  // large enough for the parallel planning and writing
  ASSERT_EQ(one.rootChild, two.rootChild);
  ASSERT_EQ(one.nodes.size(), two.nodes.size());
  ASSERT_EQ(one.blocks.size(), two.blocks.size());
  uint32_t nodes = 0, blocks = 0;
  expectDepthFirstLayout(two, two.rootChild, nodes, blocks);
  EXPECT_EQ(nodes, two.nodes.size());
  EXPECT_EQ(blocks, two.blocks.size());
  // Field by field (the records' alignment padding is never written); bounds as bits, for the NaN padding lanes.
  for (size_t i = 0; i < one.nodes.size(); ++i) {
    ASSERT_EQ(std::memcmp(one.nodes[i].bounds, two.nodes[i].bounds, sizeof(one.nodes[i].bounds)), 0) << "node " << i;
    ASSERT_EQ(std::memcmp(one.nodes[i].child, two.nodes[i].child, sizeof(one.nodes[i].child)), 0) << "node " << i;
  }
  for (size_t i = 0; i < one.blocks.size(); ++i) {
    const TriangleBlock4& a = one.blocks[i];
    const TriangleBlock4& b = two.blocks[i];
    ASSERT_EQ(std::memcmp(a.v, b.v, sizeof(a.v)), 0) << "block " << i;
    ASSERT_EQ(std::memcmp(a.geomID, b.geomID, sizeof(a.geomID)), 0) << "block " << i;
    ASSERT_EQ(std::memcmp(a.primID, b.primID, sizeof(a.primID)), 0) << "block " << i;
    ASSERT_EQ(std::memcmp(a.kind, b.kind, sizeof(a.kind)), 0) << "block " << i;
    ASSERT_EQ(a.usedMask, b.usedMask) << "block " << i;
  }
}

TEST(BuildDeterminism, WideCollapseIsTheSameOnOneAndTwoThreads) {
  expectSameWideTreeOnOneAndTwoThreads<4>();
  expectSameWideTreeOnOneAndTwoThreads<8>();
}

// Every layout: bit-identical answers from scenes built on one and on two threads.
TEST(BuildDeterminism, HitsAreTheSameOnOneAndTwoThreadsInEveryLayout) {
  const test::MeshData soup = bigSoup();
  SceneDesc desc;
  desc.meshes = {tools::backendMeshDesc(soup)};
  desc.geometryIdLimit = 1;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-0.5f, 1.5f);
  std::vector<Ray> rays(20000);
  for (Ray& ray : rays) {
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.dir = Vec3f{unit(rng), unit(rng), unit(rng)} - ray.org;
    ray.tfar = std::numeric_limits<float>::infinity();
  }
  for (AccelLayout layout : {AccelLayout::Bvh2, AccelLayout::Bvh4, AccelLayout::Bvh8, AccelLayout::Obb, AccelLayout::Hybrid}) {
    BuildOptions options;
    options.layout = layout;
    options.obbClusters = layout == AccelLayout::Obb ? 64 : 0;
    SceneAccel one, two;
    withThreads(1, [&] { one.build(desc, options); });
    withThreads(2, [&] { two.build(desc, options); });
    const QueryState state;
    size_t hits = 0;
    for (const Ray& ray : rays) {
      Ray r1 = ray, r2 = ray;
      Hit h1, h2;
      const bool f1 = one.intersect(r1, h1, state);
      ASSERT_EQ(f1, two.intersect(r2, h2, state)) << "layout " << int(layout);
      hits += f1;
      if (!f1) continue;
      ASSERT_EQ(r1.tfar, r2.tfar);
      ASSERT_EQ(h1.primID, h2.primID);
      ASSERT_EQ(h1.u, h2.u);
      ASSERT_EQ(h1.v, h2.v);
    }
    EXPECT_GT(hits, 10000u);
  }
}

}  // namespace
}  // namespace obvh
