#include "builders/morton_builder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cstdint>

#include "builders/binary_node_storage.h"
#include "memory/huge_pages.h"

namespace obvh {
namespace {

constexpr size_t kParallelThreshold = 4096;

// Spreads the low 10 bits of x so that two zero bits follow each.
uint32_t spreadBits(uint32_t x) {
  x &= 0x3FFu;
  x = (x | (x << 16)) & 0x030000FFu;
  x = (x | (x << 8)) & 0x0300F00Fu;
  x = (x | (x << 4)) & 0x030C30C3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

struct Keyed {
  uint32_t code;
  uint32_t ref;  // position in the input refs
};

class MortonBuilder {
 public:
  MortonBuilder(const std::vector<Keyed>& keys, const PrimRefs& refs, const BuildOptions& options, BinaryBvh& out)
      : keys_(keys), refs_(refs), maxLeaf_(size_t(std::max(options.maxLeafSize, 1))), out_(out) {}

  void run() {
    const size_t n = keys_.size();
    BinaryNodeStorage nodes(n);
    nodes_ = &nodes;
    build(0, 0, n);
    nodes.copyOut(out_.nodes);
    nodes_ = nullptr;
  }

 private:
  Box3f build(uint32_t nodeIndex, size_t begin, size_t end) {
    Bvh2Node& node = nodes_->make(nodeIndex);
    const size_t n = end - begin;
    if (n <= maxLeaf_) {
      Box3f box;
      for (size_t i = begin; i < end; ++i) box.extend(refs_[keys_[i].ref].bounds);
      node.bounds = box;
      node.firstChildOrPrim = uint32_t(begin);
      node.primCount = uint32_t(n);
      return box;
    }
    size_t middle = begin + n / 2;  // identical codes: halve
    const uint32_t first = keys_[begin].code, last = keys_[end - 1].code;
    if (n <= 4 * maxLeaf_) {
      // Near the leaves, cut into whole leaves: Morton cuts there leave many one- and two-triangle
      // leaves, i.e. mostly empty four-triangle blocks after the wide collapse.
      middle = begin + std::min(n - 1, ((n + 1) / 2 + maxLeaf_ - 1) / maxLeaf_ * maxLeaf_);
    } else if (first != last) {
      // The first key with the highest differing bit set starts the right child.
      const uint32_t bit = 1u << (31 - __builtin_clz(first ^ last));
      const auto split = std::partition_point(keys_.begin() + long(begin), keys_.begin() + long(end),
                                              [&](const Keyed& k) { return (k.code & bit) == 0; });
      middle = size_t(split - keys_.begin());
    }
    const uint32_t left = nodes_->claimPair();
    node.firstChildOrPrim = left;
    node.primCount = 0;
    Box3f leftBox, rightBox;
    if (n > kParallelThreshold) {
      tbb::parallel_invoke([&] { leftBox = build(left, begin, middle); }, [&] { rightBox = build(left + 1, middle, end); });
    } else {
      leftBox = build(left, begin, middle);
      rightBox = build(left + 1, middle, end);
    }
    Box3f box = leftBox;
    box.extend(rightBox);
    node.bounds = box;  // nodes are preallocated: the reference stays valid
    return box;
  }

  const std::vector<Keyed>& keys_;
  const PrimRefs& refs_;
  size_t maxLeaf_;
  BinaryBvh& out_;
  BinaryNodeStorage* nodes_ = nullptr;  // the tree's nodes while run() makes them
};

}  // namespace

BinaryBvh buildMorton(PrimRefs& refs, const BuildOptions& options) {
  BinaryBvh out;
  const size_t n = refs.size();
  if (n == 0) return out;
  const Box3f centroids = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 8192), Box3f{},
      [&](const tbb::blocked_range<size_t>& r, Box3f box) {
        for (size_t i = r.begin(); i < r.end(); ++i) box.extend(refs[i].bounds.center2());
        return box;
      },
      [](Box3f a, const Box3f& b) {
        a.extend(b);
        return a;
      });
  const Vec3f extent = centroids.upper - centroids.lower;
  Vec3f scale;
  for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.f ? 1023.99f / extent[a] : 0.f;
  std::vector<Keyed> keys;
  reserveWithHugePages(keys, n);
  keys.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const Vec3f c = refs[i].bounds.center2() - centroids.lower;
      const auto quantise = [&](int a) { return uint32_t(std::clamp(c[a] * scale[a], 0.f, 1023.f)); };
      keys[i] = {(spreadBits(quantise(0)) << 2) | (spreadBits(quantise(1)) << 1) | spreadBits(quantise(2)), uint32_t(i)};
    }
  });
  tbb::parallel_sort(keys.begin(), keys.end(), [&](const Keyed& a, const Keyed& b) {
    return a.code < b.code || (a.code == b.code && refs[a.ref].index < refs[b.ref].index);
  });
  MortonBuilder(keys, refs, options, out).run();
  reserveWithHugePages(out.primIndices, n);
  out.primIndices.resize(n);
  PrimRefs sorted;
  reserveWithHugePages(sorted, n);
  sorted.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) sorted[i] = refs[keys[i].ref], out.primIndices[i] = sorted[i].index;
  });
  refs.swap(sorted);
  return out;
}

}  // namespace obvh
