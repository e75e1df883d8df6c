// Near-to-far order of the children a ray enters, for the single-ray walk (wide_walk.h) when three
// or more of a node's children are entered. Each child becomes one 64-bit key, its entry distance
// above its lane, so that comparing keys as integers compares distances and breaks ties by the
// lower lane, the order the walk has always used; the keys are then sorted by a network of
// compare-exchanges, which compile to conditional moves. The insertion sort this replaces branched
// on every comparison of distances that nothing predicts (callgrind, bunny primary rays that hit:
// 167 instructions each time a node had three or more entered children, 0.87 times a ray).
#pragma once

#include <cstdint>
#include <cstring>

namespace obvh {

// The key of lane `lane` entered at distance t: t's bits made to order as the floats do (negative
// distances, which rays with a negative tnear can have, below positive ones) in the upper half.
// The one difference from comparing floats: -0 orders below +0 instead of tying with it.
[[gnu::always_inline]] inline int64_t childOrderKey(float t, int lane) {
  int32_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  bits ^= (bits >> 31) & 0x7FFFFFFF;  // negative floats: reverse their order, keep them negative
  return int64_t(uint64_t(int64_t(bits)) << 32 | uint32_t(lane));
}
// The same key for a distance known to be +0 or positive (the integer node tests' entries, which
// are at least tnear >= +0): its bits already order as the float does, and the sign fix above is
// three instructions a key that change nothing.
[[gnu::always_inline]] inline int64_t childOrderKeyOfNonNegative(float t, int lane) {
  uint32_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  return int64_t(uint64_t(bits) << 32 | uint32_t(lane));
}
[[gnu::always_inline]] inline int childOrderLane(int64_t key) { return int(uint32_t(key)); }

// a <= b afterwards.
[[gnu::always_inline]] inline void compareExchange(int64_t& a, int64_t& b) {
  const int64_t low = a < b ? a : b, high = a < b ? b : a;
  a = low;
  b = high;
}

// Sorts keys[0..n) ascending, 3 <= n <= 8: optimal networks for three and four keys; five to
// eight keys are padded with the largest key to eight (Batcher's 19 exchanges).
[[gnu::always_inline]] inline void sortChildOrderKeys(int64_t keys[8], int n) {
  if (n == 3) {
    compareExchange(keys[0], keys[1]);
    compareExchange(keys[1], keys[2]);
    compareExchange(keys[0], keys[1]);
    return;
  }
  if (n == 4) {
    compareExchange(keys[0], keys[1]);
    compareExchange(keys[2], keys[3]);
    compareExchange(keys[0], keys[2]);
    compareExchange(keys[1], keys[3]);
    compareExchange(keys[1], keys[2]);
    return;
  }
  for (int k = n; k < 8; ++k) keys[k] = INT64_MAX;
  static constexpr int kNetwork[19][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3}, {4, 6},
                                          {5, 7}, {1, 2}, {5, 6}, {0, 4}, {1, 5}, {2, 6}, {3, 7},
                                          {2, 4}, {3, 5}, {1, 2}, {3, 4}, {5, 6}};
  for (const auto& pair : kNetwork) compareExchange(keys[pair[0]], keys[pair[1]]);
}

}  // namespace obvh
