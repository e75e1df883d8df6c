// The shared single-ray walk (wide_walk.h) on hand-made trees whose nodes say which children a ray
// enters. Its onEntering hook runs exactly once, before the first leaf, once the start node lets the
// ray in, and never for a ray that the start node turns away; the leaves are visited in the same
// order as by the walk without the hook. A closest-hit walk takes a new tfar into its limits after
// a leaf that reports it shortened the ray, and only then; an any-hit walk stops at a report.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "traversal/wide_walk.h"

namespace obvh {
namespace {

constexpr int kWidth = 4;
using Codes = WideNode<kWidth>;

uint32_t leaf(uint32_t firstBlock) { return Codes::kLeafFlag | (firstBlock << 4) | 1u; }

// Node i's children and the lanes a ray enters, with entry distances that order them.
struct FakeNode {
  uint32_t child[kWidth];
  int entered;
  float entry[kWidth];
};

struct FakeNodes {
  const std::vector<FakeNode>& tree;
  const uint32_t* children(uint32_t node) const { return tree[node].child; }
  static constexpr bool kEntriesNonNegative = false;
  float exitLimit(float tfar) const { return tfar; }
  int enter(uint32_t node, float, float, float entry[kWidth]) const {
    for (int lane = 0; lane < kWidth; ++lane) entry[lane] = tree[node].entry[lane];
    return tree[node].entered;
  }
  void prefetch(uint32_t) const {}
  void count(uint32_t, TraversalCounters&) const {}
};

// The segment [0, 100] along +x (the fake nodes decide what it enters).
Ray rayAlongX() {
  Ray ray;
  ray.org = {0.f, 0.f, 0.f};
  ray.dir = {1.f, 0.f, 0.f};
  ray.tnear = 0.f;
  ray.tfar = 100.f;
  return ray;
}

// The leaves' first blocks in visiting order, with the hook's calls marked as -1.
std::vector<int> walkLog(const std::vector<FakeNode>& tree, uint32_t start, bool withHook) {
  Ray ray = rayAlongX();
  std::vector<int> log;
  const auto visit = [&](uint32_t firstBlock, uint32_t) {
    log.push_back(int(firstBlock));
    return false;
  };
  if (withHook)
    walkWideTree<kWidth, true, false>(FakeNodes{tree}, start, ray, visit, nullptr, [&] { log.push_back(-1); });
  else
    walkWideTree<kWidth, true, false>(FakeNodes{tree}, start, ray, visit, nullptr);
  return log;
}

const float kFar[kWidth] = {4.f, 3.f, 2.f, 1.f};  // lane 3 nearest

TEST(WalkOnEntering, RunsOnceBeforeTheFirstLeafAndKeepsTheOrder) {
  // Root: enters nodes 1 and 2 and leaf 7; node 1 enters leaves 10 and 11; node 2 one leaf, 20.
  const uint32_t empty = Codes::kEmptyChild;
  const std::vector<FakeNode> tree = {
      {{1, 2, leaf(7), empty}, 0b0111, {1.f, 2.f, 3.f, 0.f}},
      {{leaf(10), leaf(11), empty, empty}, 0b0011, {kFar[0], kFar[1], 0.f, 0.f}},
      {{leaf(20), empty, empty, empty}, 0b0001, {0.f, 0.f, 0.f, 0.f}},
  };
  const std::vector<int> plain = walkLog(tree, 0, false);
  const std::vector<int> hooked = walkLog(tree, 0, true);
  EXPECT_EQ(plain, (std::vector<int>{11, 10, 20, 7}));
  std::vector<int> expected = plain;
  expected.insert(expected.begin(), -1);
  EXPECT_EQ(hooked, expected);
}

TEST(WalkOnEntering, RunsForEveryEnteredStartIncludingSingleChildren) {
  const uint32_t empty = Codes::kEmptyChild;
  const std::vector<FakeNode> tree = {
      {{1, empty, empty, empty}, 0b0001, {0.f, 0.f, 0.f, 0.f}},
      {{leaf(5), leaf(6), leaf(8), leaf(9)}, 0b1111, {kFar[0], kFar[1], kFar[2], kFar[3]}},
  };
  EXPECT_EQ(walkLog(tree, 0, true), (std::vector<int>{-1, 9, 8, 6, 5}));
  // Starting below the root, as a packet hands a ray over mid-tree.
  EXPECT_EQ(walkLog(tree, 1, true), (std::vector<int>{-1, 9, 8, 6, 5}));
}

TEST(WalkOnEntering, NeverRunsForARayTheStartNodeTurnsAway) {
  const uint32_t empty = Codes::kEmptyChild;
  const std::vector<FakeNode> tree = {
      {{leaf(1), leaf(2), empty, empty}, 0, {0.f, 0.f, 0.f, 0.f}},
  };
  EXPECT_TRUE(walkLog(tree, 0, true).empty());
}

TEST(WalkOnEntering, RunsBeforeAStartThatIsALeaf) {
  const std::vector<FakeNode> tree;
  EXPECT_EQ(walkLog(tree, leaf(3), true), (std::vector<int>{-1, 3}));
}

// Root: leaf 1 entered at 1, leaf 2 at 5. Leaf 1 sets tfar to newTfar and returns `report`.
std::vector<int> limitLog(bool closest, float newTfar, bool report) {
  const uint32_t empty = Codes::kEmptyChild;
  const std::vector<FakeNode> tree = {
      {{leaf(1), leaf(2), empty, empty}, 0b0011, {1.f, 5.f, 0.f, 0.f}},
  };
  Ray ray = rayAlongX();
  std::vector<int> log;
  const auto visit = [&](uint32_t firstBlock, uint32_t) {
    log.push_back(int(firstBlock));
    if (firstBlock != 1) return false;
    ray.tfar = newTfar;
    return report;
  };
  if (closest)
    walkWideTree<kWidth, true, false>(FakeNodes{tree}, 0, ray, visit, nullptr);
  else
    walkWideTree<kWidth, false, false>(FakeNodes{tree}, 0, ray, visit, nullptr);
  return log;
}

TEST(WalkLimits, ALeafThatShortensTheRayDropsTheChildrenBeyondIt) {
  EXPECT_EQ(limitLog(true, 2.f, true), (std::vector<int>{1}));
  // Entered exactly at the new tfar: only hits at that same distance could lie there (wide_walk.h).
  EXPECT_EQ(limitLog(true, 5.f, true), (std::vector<int>{1}));
  // Still within reach of the shortened ray.
  EXPECT_EQ(limitLog(true, 6.f, true), (std::vector<int>{1, 2}));
}

TEST(WalkLimits, ALeafThatReportsNothingLeavesTheLimits) {
  // The contract the closest-hit visitors keep: without a report the walk does not reread tfar.
  EXPECT_EQ(limitLog(true, 2.f, false), (std::vector<int>{1, 2}));
}

TEST(WalkLimits, AnAnyHitWalkStopsAtAReport) {
  EXPECT_EQ(limitLog(false, 100.f, true), (std::vector<int>{1}));
  EXPECT_EQ(limitLog(false, 100.f, false), (std::vector<int>{1, 2}));
}

}  // namespace
}  // namespace obvh
