// The near-to-far order of three or more entered children (traversal/child_order.h): the keys sort
// by entry distance as floats compare, ties by the lower lane, for every count the walk meets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <tuple>
#include <vector>

#include "traversal/child_order.h"

namespace obvh {
namespace {

// The order the walk's insertion sort produced: distance, then lane.
std::vector<int> referenceOrder(const std::vector<float>& t) {
  std::vector<int> lanes(t.size());
  std::iota(lanes.begin(), lanes.end(), 0);
  std::stable_sort(lanes.begin(), lanes.end(), [&](int a, int b) { return t[a] < t[b]; });
  return lanes;
}

std::vector<int> networkOrder(const std::vector<float>& t) {
  int64_t keys[8];
  for (size_t lane = 0; lane < t.size(); ++lane) keys[lane] = childOrderKey(t[lane], int(lane));
  sortChildOrderKeys(keys, int(t.size()));
  std::vector<int> lanes;
  for (size_t k = 0; k < t.size(); ++k) lanes.push_back(childOrderLane(keys[k]));
  return lanes;
}

TEST(ChildOrder, KeysCompareAsTheirDistancesThenLanes) {
  const float values[] = {-std::numeric_limits<float>::infinity(), -3.5f, -1e-30f, 0.f, 1e-40f, 1e-30f, 2.f,
                          2.5f, 1e30f, std::numeric_limits<float>::infinity()};
  for (float a : values)
    for (float b : values)
      for (int la = 0; la < 8; ++la)
        for (int lb = 0; lb < 8; ++lb)
          EXPECT_EQ(childOrderKey(a, la) < childOrderKey(b, lb), std::make_tuple(a, la) < std::make_tuple(b, lb))
              << a << " lane " << la << " vs " << b << " lane " << lb;
}

// The integer node tests' entries are +0 or positive: their keys without the sign fix are the
// same keys, so both walks visit in one order.
TEST(ChildOrder, NonNegativeKeysEqualTheGeneralKeys) {
  const float values[] = {0.f, 1e-45f, 1e-40f, 1e-30f, 1.f, 2.5f, 1e30f, std::numeric_limits<float>::max(),
                          std::numeric_limits<float>::infinity()};
  for (float t : values)
    for (int lane = 0; lane < 8; ++lane)
      EXPECT_EQ(childOrderKeyOfNonNegative(t, lane), childOrderKey(t, lane)) << t << " lane " << lane;
}

// Every arrangement of n distances drawn from few values (so ties are common) for n = 3..8, and
// random distances of both signs.
TEST(ChildOrder, SortsEveryCountLikeTheStableSortByDistance) {
  for (int n = 3; n <= 8; ++n) {
    const float levels[] = {0.f, 1.f, 2.f};
    std::vector<int> digits(size_t(n), 0);
    for (;;) {
      std::vector<float> t;
      for (int d : digits) t.push_back(levels[d]);
      ASSERT_EQ(networkOrder(t), referenceOrder(t)) << "n = " << n;
      int k = 0;
      while (k < n && ++digits[size_t(k)] == 3) digits[size_t(k++)] = 0;
      if (k == n) break;
    }
  }
  std::mt19937 random(7);
  std::uniform_real_distribution<float> distance(-100.f, 100.f);
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<float> t(size_t(3 + trial % 6));
    for (float& x : t) x = distance(random);
    ASSERT_EQ(networkOrder(t), referenceOrder(t)) << "trial " << trial;
  }
}

}  // namespace
}  // namespace obvh
