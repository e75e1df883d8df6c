// Structural invariants of the binned-SAH builder, on random and degenerate inputs.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "builders/binned_sah_builder.h"

namespace obvh {
namespace {

PrimRefs randomBoxes(size_t n, uint32_t seed, float spread) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  PrimRefs refs(n, PrimRef{});
  for (size_t i = 0; i < n; ++i) {
    const Vec3f c{unit(rng) * spread, unit(rng) * spread, unit(rng) * spread};
    const Vec3f h{unit(rng) * 0.01f, unit(rng) * 0.01f, unit(rng) * 0.01f};
    refs[i].bounds.extend(c - h);
    refs[i].bounds.extend(c + h);
    refs[i].index = uint32_t(i);
  }
  return refs;
}

bool contains(const Box3f& outer, const Box3f& inner) {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y && outer.lower.z <= inner.lower.z &&
         outer.upper.x >= inner.upper.x && outer.upper.y >= inner.upper.y && outer.upper.z >= inner.upper.z;
}

// Walks the tree: every primitive appears in exactly one leaf, children lie inside parents, leaves
// respect the size limit. Returns the depth.
int checkTree(const BinaryBvh& bvh, const PrimRefs& original, int maxLeafSize) {
  std::vector<int> seen(original.size(), 0);
  int maxDepth = 0;
  std::vector<std::pair<uint32_t, int>> stack = {{0u, 1}};
  while (!stack.empty()) {
    auto [index, depth] = stack.back();
    stack.pop_back();
    maxDepth = std::max(maxDepth, depth);
    const Bvh2Node& node = bvh.nodes.at(index);
    if (node.isLeaf()) {
      EXPECT_LE(node.primCount, uint32_t(maxLeafSize));
      for (uint32_t i = 0; i < node.primCount; ++i) {
        const uint32_t prim = bvh.primIndices.at(node.firstChildOrPrim + i);
        ++seen.at(prim);
        EXPECT_TRUE(contains(node.bounds, original[prim].bounds));
      }
      continue;
    }
    for (uint32_t c = 0; c < 2; ++c) {
      EXPECT_TRUE(contains(node.bounds, bvh.nodes.at(node.firstChildOrPrim + c).bounds));
      stack.push_back({node.firstChildOrPrim + c, depth + 1});
    }
  }
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "primitive " << i;
  return maxDepth;
}

TEST(BinnedSahBuilder, EmptyInputGivesEmptyTree) {
  PrimRefs refs;
  EXPECT_TRUE(buildBinnedSah(refs, BuildOptions{}).empty());
}

TEST(BinnedSahBuilder, RandomBoxesFormAValidTree) {
  for (size_t n : {1u, 2u, 7u, 1000u, 200000u}) {
    PrimRefs refs = randomBoxes(n, uint32_t(n), 10.f);
    const PrimRefs original = refs;
    BuildOptions options;
    const BinaryBvh bvh = buildBinnedSah(refs, options);
    const int depth = checkTree(bvh, original, options.maxLeafSize);
    EXPECT_LE(depth, 100) << n;
  }
}

TEST(BinnedSahBuilder, IdenticalPrimitivesStillSplitIntoSmallLeaves) {
  PrimRefs refs(5000, PrimRef{});
  for (size_t i = 0; i < refs.size(); ++i) {
    refs[i].bounds.extend({1.f, 2.f, 3.f});
    refs[i].bounds.extend({1.5f, 2.5f, 3.5f});
    refs[i].index = uint32_t(i);
  }
  const PrimRefs original = refs;
  const BinaryBvh bvh = buildBinnedSah(refs, BuildOptions{});
  EXPECT_LE(checkTree(bvh, original, 4), 20);
}

TEST(BinnedSahBuilder, ExponentiallySpreadPrimitivesKeepBoundedDepth) {
  PrimRefs refs(100000, PrimRef{});
  for (size_t i = 0; i < refs.size(); ++i) {
    const float x = std::ldexp(1.f, int(i % 100) - 50);
    refs[i].bounds.extend({x, 0.f, 0.f});
    refs[i].bounds.extend({x * 1.0001f, 1e-3f, 1e-3f});
    refs[i].index = uint32_t(i);
  }
  const PrimRefs original = refs;
  const BinaryBvh bvh = buildBinnedSah(refs, BuildOptions{});
  EXPECT_LE(checkTree(bvh, original, 4), 48 + 20);
}

TEST(BinnedSahBuilder, SahCostIsFarBelowTestingEveryPrimitive) {
  // SAH cost (expected node visits plus primitive tests per ray, relative to the root's area) of a
  // tree over small scattered boxes must be a small fraction of the cost of one flat leaf (n tests).
  PrimRefs refs = randomBoxes(4096, 5, 10.f);
  const BinaryBvh bvh = buildBinnedSah(refs, BuildOptions{});
  double cost = 0.0;
  const double rootArea = bvh.nodes[0].bounds.halfArea();
  for (const Bvh2Node& node : bvh.nodes)
    cost += node.bounds.halfArea() / rootArea * (node.isLeaf() ? double(node.primCount) : 1.0);
  EXPECT_GT(cost, 1.0);
  EXPECT_LT(cost, 4096.0 / 50.0);
}

}  // namespace
}  // namespace obvh
