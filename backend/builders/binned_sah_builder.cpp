#include "builders/binned_sah_builder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <emmintrin.h>
#include <limits>
#include <memory>

#include "builders/binary_node_storage.h"
#include "memory/huge_pages.h"
#include "simd/float4_sse.h"

namespace obvh {
namespace {

constexpr int kMaxBins = 256;
// Below these sizes the overhead of spawning tasks outweighs the parallel speed-up.
constexpr size_t kParallelBinningThreshold = 1 << 16;
constexpr size_t kParallelRecursionThreshold = 1 << 12;
// Past this depth the builder splits at the object median, which bounds the depth by
// kMedianSplitDepth + log2(N) and so keeps traversal stacks small and fixed.
constexpr int kMedianSplitDepth = 48;



// A box as two SSE vectors (lane 3 unused): binning extends a bin with two min/max instructions.
struct SseBox {
  simd::Float4Sse lower = simd::Float4Sse::broadcast(std::numeric_limits<float>::infinity());
  simd::Float4Sse upper = simd::Float4Sse::broadcast(-std::numeric_limits<float>::infinity());

  void extend(simd::Float4Sse lo, simd::Float4Sse hi) { lower = min(lower, lo), upper = max(upper, hi); }
  void extend(const SseBox& b) { extend(b.lower, b.upper); }
  // dx * dy + dy * dz + dz * dx with the scalar operations' rounding, the three products in one
  // SSE multiplication (the SAH sweeps call this for every bin of every node; a store and scalar
  // reload here was a fair share of the build).
  float halfArea() const {
    const __m128 d = _mm_sub_ps(upper.v, lower.v);
    // Empty on some axis: for finite bounds, hi - lo < 0 exactly when lo > hi.
    if (_mm_movemask_ps(_mm_cmplt_ps(d, _mm_setzero_ps())) & 7) return 0.f;
    const __m128 products = _mm_mul_ps(d, _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1)));  // dx*dy, dy*dz, dz*dx
    const float xy = _mm_cvtss_f32(products);
    const float yz = _mm_cvtss_f32(_mm_shuffle_ps(products, products, _MM_SHUFFLE(1, 1, 1, 1)));
    const float zx = _mm_cvtss_f32(_mm_movehl_ps(products, products));
    return xy + yz + zx;
  }
};

// A primitive's bounds as loaded by SSE: lane 3 of lower is upper.x and lane 3 of upper the index
// bits, both ignored (PrimRef is a packed Box3f followed by the index).
static_assert(sizeof(Box3f) == 6 * sizeof(float) && offsetof(PrimRef, index) == sizeof(Box3f));
inline simd::Float4Sse refLower(const PrimRef& ref) { return simd::Float4Sse::loadUnaligned(&ref.bounds.lower.x); }
inline simd::Float4Sse refUpper(const PrimRef& ref) { return simd::Float4Sse::loadUnaligned(&ref.bounds.upper.x); }

Box3f toBox3f(const SseBox& box) {
  alignas(16) float lo[4], hi[4];
  box.lower.store(lo), box.upper.store(hi);
  Box3f out;
  out.lower = {lo[0], lo[1], lo[2]};
  out.upper = {hi[0], hi[1], hi[2]};
  return out;
}

// Bounds of a range of primitives and of their doubled centroids (see Box3f::center2).
struct RangeInfo {
  SseBox box;
  SseBox centroids;

  void add(const PrimRef& ref) {
    const simd::Float4Sse lower = refLower(ref), upper = refUpper(ref);
    box.extend(lower, upper);
    const simd::Float4Sse centre2 = lower + upper;
    centroids.extend(centre2, centre2);
  }
  void merge(const RangeInfo& other) {
    box.extend(other.box);
    centroids.extend(other.centroids);
  }
  Box3f bounds() const { return toBox3f(box); }
  Box3f centroidBounds() const { return toBox3f(centroids); }
};

// Per-axis bin bounds and counts. Bounds are laid out axis-major in the first 3 * binCount
// entries; counts bin-major, the three axes' counts of a bin in one four-lane group (lane 3 stays
// zero), which the SAH sweep loads as the lanes of its three axes. Fixed storage: a sequential
// node reuses its thread's scratch Bins instead of allocating.
struct Bins {
  int binCount = 0;
  std::array<SseBox, 3 * kMaxBins> boundsStorage;
  alignas(16) std::array<uint32_t, 4 * kMaxBins> countStorage;

  void reset(int bins) {
    binCount = bins;
    std::fill_n(boundsStorage.begin(), 3 * bins, SseBox{});
    std::fill_n(countStorage.begin(), 4 * bins, 0u);
  }
  SseBox& bounds(int axis, int b) { return boundsStorage[size_t(axis) * binCount + b]; }
  const SseBox& bounds(int axis, int b) const { return boundsStorage[size_t(axis) * binCount + b]; }
  uint32_t& count(int axis, int b) { return countStorage[size_t(b) * 4 + axis]; }
  // Bin b's counts along x, y, z in lanes 0-2.
  __m128i countLanes(int b) const { return _mm_load_si128(reinterpret_cast<const __m128i*>(&countStorage[size_t(b) * 4])); }

  void merge(const Bins& other) {
    for (size_t i = 0; i < 3 * size_t(binCount); ++i) boundsStorage[i].extend(other.boundsStorage[i]);
    for (size_t i = 0; i < 4 * size_t(binCount); ++i) countStorage[i] += other.countStorage[i];
  }
};

// SseBox::halfArea of three boxes at once, box a in lane a (lane 3 garbage): the same products and
// sums in the same order per lane, so each lane is the float halfArea() returns for its box.
inline __m128 halfAreasOfThree(const SseBox box[3]) {
  __m128 dx = _mm_sub_ps(box[0].upper.v, box[0].lower.v), dy = _mm_sub_ps(box[1].upper.v, box[1].lower.v);
  __m128 dz = _mm_sub_ps(box[2].upper.v, box[2].lower.v), unused = dz;
  _MM_TRANSPOSE4_PS(dx, dy, dz, unused);  // now dx holds every box's extent along x, and so on
  const __m128 zero = _mm_setzero_ps();
  const __m128 empty = _mm_or_ps(_mm_or_ps(_mm_cmplt_ps(dx, zero), _mm_cmplt_ps(dy, zero)), _mm_cmplt_ps(dz, zero));
  const __m128 area = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dy), _mm_mul_ps(dy, dz)), _mm_mul_ps(dz, dx));
  return _mm_andnot_ps(empty, area);
}

// The calling thread's scratch bins. Not inlined on purpose: with the thread_local's address
// visible, GCC recomputed it (a __tls_get_addr call, in the shared library) for every primitive
// binned, spilling the loop's registers around the call, instead of keeping it in a register.
[[gnu::noinline]] Bins& threadScratchBins() {
  static thread_local Bins scratch;
  return scratch;
}

struct Split {
  int axis = -1;
  int bin = 0;  // primitives in bins [0, bin) go left
  float cost = std::numeric_limits<float>::infinity();
};

// Maps a centroid to its bin on each axis; binning and partitioning use this one computation, so
// a primitive always lands on the side its bin was counted on.
struct BinMapping {
  simd::Float4Sse origin;
  simd::Float4Sse scale;
  int binCount;
  simd::Float4Sse lastBin;  // binCount - 1 in every lane

  BinMapping(const Box3f& centroidBounds, int bins) : binCount(bins), lastBin(simd::Float4Sse::broadcast(float(bins - 1))) {
    alignas(16) float o[4] = {centroidBounds.lower.x, centroidBounds.lower.y, centroidBounds.lower.z, 0.f};
    alignas(16) float k[4] = {0.f, 0.f, 0.f, 0.f};
    const Vec3f extent = centroidBounds.upper - centroidBounds.lower;
    for (int axis = 0; axis < 3; ++axis) k[axis] = extent[axis] > 0.f ? (0.99999f * float(bins)) / extent[axis] : 0.f;
    origin = simd::Float4Sse::load(o);
    scale = simd::Float4Sse::load(k);
  }
  // Bins of the box with these SSE bounds on x, y, z (out[3] is garbage). Clamped before the
  // conversion, in SIMD: for the centroids of the node's own primitives (the only ones binned)
  // the same bins as clamping the truncated integers; a NaN lands in bin 0 either way (max returns
  // its second operand for NaN).
  void bins(simd::Float4Sse lower, simd::Float4Sse upper, int out[4]) const { binValues(lower, upper).truncate(out); }
  // Bit a set when the box's bin along axis a lies below firstRight: the clamped value bins()
  // truncates, compared as a float (it lies in [0, binCount - 1], where trunc(v) < k exactly when
  // v < k), so no integers go through memory.
  int binsBelow(simd::Float4Sse lower, simd::Float4Sse upper, simd::Float4Sse firstRight) const {
    return lessMask(binValues(lower, upper), firstRight);
  }
  // The bins as floats, clamped to [0, binCount - 1], before their truncation.
  simd::Float4Sse binValues(simd::Float4Sse lower, simd::Float4Sse upper) const {
    return min(max((lower + upper - origin) * scale, simd::Float4Sse::broadcast(0.f)), lastBin);
  }
  // Whether the primitive goes to the left of split (primitives in bins [0, split.bin) do).
  bool goesLeft(const PrimRef& ref, const Split& split) const {
    return (binsBelow(refLower(ref), refUpper(ref), simd::Float4Sse::broadcast(float(split.bin))) >> split.axis) & 1;
  }
};

class BinnedSahBuilder {
 public:
  BinnedSahBuilder(PrimRefs& refs, const BuildOptions& options, BinaryBvh& out)
      : refs_(refs), options_(options), out_(out) {
    options_.binCount = std::clamp(options_.binCount, 2, kMaxBins);
    options_.maxLeafSize = std::max(options_.maxLeafSize, 1);
    options_.leafBlockSize = std::max(options_.leafBlockSize, 1);
    // The SAH sweep counts blocks per bin: a shift instead of a division when the size is a power of two.
    for (int shift = 0; shift < 31; ++shift)
      if (options_.leafBlockSize == 1 << shift) blockShift_ = shift;
  }

  void run() {
    const size_t n = refs_.size();
    out_.nodes.clear();
    out_.primIndices.clear();
    if (n == 0) return;
    buildIntoBinaryBvh(refs_, out_, [&](BinaryNodeStorage& nodes) {
      nodes_ = &nodes;
      buildNode(0, 0, n, rangeInfo(0, n), 0, Scratch{});
      nodes_ = nullptr;
    });
  }

 private:
  RangeInfo rangeInfo(size_t begin, size_t end) const {
    if (end - begin < kParallelBinningThreshold) {
      RangeInfo info;
      for (size_t i = begin; i < end; ++i) info.add(refs_[i]);
      return info;
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(begin, end, 4096), RangeInfo{},
        [&](const tbb::blocked_range<size_t>& r, RangeInfo info) {
          for (size_t i = r.begin(); i < r.end(); ++i) info.add(refs_[i]);
          return info;
        },
        [](RangeInfo a, const RangeInfo& b) {
          a.merge(b);
          return a;
        });
  }

  void binRange(size_t begin, size_t end, const BinMapping& mapping, Bins& bins) const {
    for (size_t i = begin; i < end; ++i) {
      const simd::Float4Sse lower = refLower(refs_[i]), upper = refUpper(refs_[i]);
      int b[4];
      mapping.bins(lower, upper, b);
      for (int axis = 0; axis < 3; ++axis) {
        bins.bounds(axis, b[axis]).extend(lower, upper);
        ++bins.count(axis, b[axis]);
      }
    }
  }

  // Bins of [begin, end); small ranges fill the calling thread's scratch, large ones reduce in parallel into `large`.
  const Bins& binAll(size_t begin, size_t end, const BinMapping& mapping, std::unique_ptr<Bins>& large) const {
    const int binCount = mapping.binCount;
    if (end - begin < kParallelBinningThreshold) {
      Bins& scratch = threadScratchBins();
      scratch.reset(binCount);
      binRange(begin, end, mapping, scratch);
      return scratch;
    }
    auto empty = std::make_unique<Bins>();
    empty->reset(binCount);
    large = std::make_unique<Bins>(tbb::parallel_reduce(
        tbb::blocked_range<size_t>(begin, end, 8192), *empty,
        [&](const tbb::blocked_range<size_t>& r, Bins bins) {
          binRange(r.begin(), r.end(), mapping, bins);
          return bins;
        },
        [](Bins a, const Bins& b) {
          a.merge(b);
          return a;
        }));
    return *large;
  }

  // Leaves are tested leafBlockSize primitives at a time: a partly filled block costs a full one.
  float blocks(size_t count) const {
    if (blockShift_ >= 0) return float((count + (size_t(1) << blockShift_) - 1) >> blockShift_);
    const size_t b = size_t(options_.leafBlockSize);
    return float((count + b - 1) / b);
  }

  // blocks() of three counts at once (lanes 0-2), exact: a count of a node below 2^31 primitives
  // converts as the scalar conversion does.
  __m128 blockLanes(__m128i counts) const {
    if (blockShift_ >= 0) {
      const __m128i rounded = _mm_add_epi32(counts, _mm_set1_epi32((1 << blockShift_) - 1));
      return _mm_cvtepi32_ps(_mm_srl_epi32(rounded, _mm_cvtsi32_si128(blockShift_)));
    }
    alignas(16) uint32_t c[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(c), counts);
    return _mm_setr_ps(blocks(c[0]), blocks(c[1]), blocks(c[2]), 0.f);
  }

  // The split of least SAH cost over every bin boundary of the three axes; on equal costs the
  // lowest axis, then the lowest boundary. The three axes are swept together as the lanes of one
  // sweep (lane a: axis a), each lane with the scalar sweep's operations in its order, so the
  // costs are the same floats (swept axis by axis, with a box's area through scalar extractions,
  // the sweeps were a sixth of a bunny build's instructions).
  Split findBestSplit(const Bins& bins, int binCount) const {
    // Every entry read below is written first: no zero fill (it showed up as a memset per node).
    alignas(16) std::array<float, 4 * kMaxBins> rightCost;
    alignas(16) std::array<int32_t, 4 * kMaxBins> rightCount;
    SseBox accumulated[3];
    __m128i count = _mm_setzero_si128();
    for (int b = binCount - 1; b > 0; --b) {
      for (int axis = 0; axis < 3; ++axis) accumulated[axis].extend(bins.bounds(axis, b));
      count = _mm_add_epi32(count, bins.countLanes(b));
      _mm_store_ps(&rightCost[size_t(b) * 4], _mm_mul_ps(halfAreasOfThree(accumulated), blockLanes(count)));
      _mm_store_si128(reinterpret_cast<__m128i*>(&rightCount[size_t(b) * 4]), count);
    }
    for (SseBox& box : accumulated) box = SseBox{};
    count = _mm_setzero_si128();
    const __m128i none = _mm_setzero_si128();
    __m128 bestCost = _mm_set1_ps(std::numeric_limits<float>::infinity());
    __m128i bestBin = _mm_setzero_si128();
    for (int b = 1; b < binCount; ++b) {
      for (int axis = 0; axis < 3; ++axis) accumulated[axis].extend(bins.bounds(axis, b - 1));
      count = _mm_add_epi32(count, bins.countLanes(b - 1));
      const __m128 cost = _mm_add_ps(_mm_mul_ps(halfAreasOfThree(accumulated), blockLanes(count)),
                                     _mm_load_ps(&rightCost[size_t(b) * 4]));
      const __m128i rightCounts = _mm_load_si128(reinterpret_cast<const __m128i*>(&rightCount[size_t(b) * 4]));
      const __m128 better = _mm_and_ps(
          _mm_castsi128_ps(_mm_and_si128(_mm_cmpgt_epi32(count, none), _mm_cmpgt_epi32(rightCounts, none))),
          _mm_cmplt_ps(cost, bestCost));
      bestCost = _mm_or_ps(_mm_and_ps(better, cost), _mm_andnot_ps(better, bestCost));
      const __m128i takeBin = _mm_castps_si128(better);
      bestBin = _mm_or_si128(_mm_and_si128(takeBin, _mm_set1_epi32(b)), _mm_andnot_si128(takeBin, bestBin));
    }
    alignas(16) float costs[4];
    alignas(16) int32_t bin[4];
    _mm_store_ps(costs, bestCost);
    _mm_store_si128(reinterpret_cast<__m128i*>(bin), bestBin);
    Split best;
    for (int axis = 0; axis < 3; ++axis)
      if (costs[axis] < best.cost) best = Split{axis, bin[axis], costs[axis]};
    return best;
  }

  // Where partitionMeasuring copies refs_[i]: slots[i - first]. A subtree below
  // kParallelBinningThreshold primitives allocates one for all its partitions (its parallel
  // subtrees use disjoint parts): small enough for the allocator to hand the same memory to the
  // next subtree, where one table for the whole build (the dragon's 24 MB) would be fresh pages to
  // fault in at every build.
  struct Scratch {
    PrimRef* slots = nullptr;
    size_t first = 0;
    PrimRef& operator[](size_t i) const { return slots[i - first]; }
  };

  // Partitions [begin, end) by the split and measures both sides. Out of place, without branches on
  // the side: each primitive is copied to the scratch's next slot on its side (the left side from
  // begin up, the right from end down), then the sides are measured and copied back. In place, with
  // a loop per side as in Hoare's partition, the branches on the primitives' sides were mispredicted
  // 0.4 million times a bunny build (callgrind's branch simulation) and the partition took about a
  // quarter of the build's time (perf). Returns the first index of the right side.
  size_t partitionMeasuring(size_t begin, size_t end, const BinMapping& mapping, const Split& split,
                            const Scratch& scratch, RangeInfo& left, RangeInfo& right) {
    PrimRef* refs = refs_.data();
    size_t nextLeft = begin, nextRight = end;
    for (size_t i = begin; i < end; ++i) {
      const size_t toLeft = mapping.goesLeft(refs[i], split);
      nextRight -= toLeft ^ 1;
      copyRef(refs[i], scratch[toLeft ? nextLeft : nextRight]);
      nextLeft += toLeft;
    }
    RangeInfo l, r;
    for (size_t i = begin; i < nextLeft; ++i) l.add(scratch[i]);
    for (size_t i = nextLeft; i < end; ++i) r.add(scratch[i]);
    std::memcpy(refs + begin, &scratch[begin], (end - begin) * sizeof(PrimRef));
    left = l;
    right = r;
    return nextLeft;
  }

  // A PrimRef (28 bytes) as two overlapping 16-byte moves.
  static void copyRef(const PrimRef& from, PrimRef& to) {
    static_assert(sizeof(PrimRef) == 28);
    const char* src = reinterpret_cast<const char*>(&from);
    char* dst = reinterpret_cast<char*>(&to);
    const __m128 head = _mm_loadu_ps(reinterpret_cast<const float*>(src));
    const __m128 tail = _mm_loadu_ps(reinterpret_cast<const float*>(src + 12));
    _mm_storeu_ps(reinterpret_cast<float*>(dst), head);
    _mm_storeu_ps(reinterpret_cast<float*>(dst + 12), tail);
  }

  void makeLeaf(uint32_t nodeIndex, size_t begin, size_t end, const Box3f& bounds) {
    Bvh2Node& node = nodes_->make(nodeIndex);
    node.bounds = bounds;
    node.firstChildOrPrim = uint32_t(begin);
    node.primCount = uint32_t(end - begin);
  }

  void buildNode(uint32_t nodeIndex, size_t begin, size_t end, const RangeInfo& info, int depth, Scratch scratch) {
    const size_t n = end - begin;
    if (n == 1) return makeLeaf(nodeIndex, begin, end, info.bounds());
    // Raw bytes: every slot is written before it is read (PrimRef's initializers would be a pass).
    std::unique_ptr<unsigned char[]> ownScratch;
    if (scratch.slots == nullptr && n < kParallelBinningThreshold) {
      ownScratch.reset(new unsigned char[n * sizeof(PrimRef)]);
      scratch = Scratch{reinterpret_cast<PrimRef*>(ownScratch.get()), begin};
    }

    size_t middle = begin;
    RangeInfo leftInfo, rightInfo;
    bool childInfoKnown = false;  // set when the partition already measured both sides
    // Small nodes cannot use many bins; sweeping empty bins would dominate the build time. A node
    // of n primitives gets 4 + n / 4 (at most build_bins): its splits are as good as with n bins
    // (the same or lower SAH cost on the bunny, dragon and motorBike) for 9.6% fewer build
    // instructions (dragon, callgrind; README, Performance).
    const int binCount = int(std::min<size_t>(size_t(options_.binCount), 4 + n / 4));
    const Box3f centroidBounds = info.centroidBounds();
    const BinMapping mapping(centroidBounds, binCount);
    const bool centroidsDistinct = !(centroidBounds.lower.x == centroidBounds.upper.x &&
                                     centroidBounds.lower.y == centroidBounds.upper.y &&
                                     centroidBounds.lower.z == centroidBounds.upper.z);
    if (centroidsDistinct && depth >= kMedianSplitDepth) {
      if (n <= size_t(options_.maxLeafSize)) return makeLeaf(nodeIndex, begin, end, info.bounds());
      const int axis = centroidBounds.largestAxis();
      middle = begin + n / 2;
      std::nth_element(refs_.begin() + begin, refs_.begin() + middle, refs_.begin() + end,
                       [axis](const PrimRef& a, const PrimRef& b) {
                         return a.bounds.center2()[axis] < b.bounds.center2()[axis];
                       });
    } else if (centroidsDistinct) {
      std::unique_ptr<Bins> largeBins;
      const Split split = findBestSplit(binAll(begin, end, mapping, largeBins), binCount);
      const float parentArea = info.box.halfArea();
      const float leafCost = options_.intersectionCost * blocks(n);
      const float splitCost =
          options_.traversalCost +
          (parentArea > 0.f ? options_.intersectionCost * split.cost / parentArea : leafCost);
      if (n <= size_t(options_.maxLeafSize) && leafCost <= splitCost)
        return makeLeaf(nodeIndex, begin, end, info.bounds());
      if (split.axis >= 0) {
        if (n < kParallelBinningThreshold) {
          middle = partitionMeasuring(begin, end, mapping, split, scratch, leftInfo, rightInfo);
          childInfoKnown = true;
        } else {  // large ranges: measure the children with the parallel reduction instead
          auto goesLeft = [&](const PrimRef& ref) { return mapping.goesLeft(ref, split); };
          middle = size_t(std::partition(refs_.begin() + begin, refs_.begin() + end, goesLeft) - refs_.begin());
        }
      }
    } else if (n <= size_t(options_.maxLeafSize)) {
      return makeLeaf(nodeIndex, begin, end, info.bounds());
    }
    // Identical centroids or a failed partition: halve the range so recursion always terminates.
    if (middle == begin || middle == end) {
      middle = begin + n / 2;
      childInfoKnown = false;
    }

    const uint32_t left = nodes_->claimPair();
    Bvh2Node& node = nodes_->make(nodeIndex);
    node.bounds = info.bounds();
    node.firstChildOrPrim = left;
    node.primCount = 0;

    auto buildLeft = [&] {
      buildNode(left, begin, middle, childInfoKnown ? leftInfo : rangeInfo(begin, middle), depth + 1, scratch);
    };
    auto buildRight = [&] {
      buildNode(left + 1, middle, end, childInfoKnown ? rightInfo : rangeInfo(middle, end), depth + 1, scratch);
    };
    if (n > kParallelRecursionThreshold) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
  }

  int blockShift_ = -1;
  PrimRefs& refs_;
  BuildOptions options_;
  BinaryBvh& out_;
  BinaryNodeStorage* nodes_ = nullptr;  // the tree's nodes while run() makes them
};

}  // namespace

BinaryBvh buildBinnedSah(PrimRefs& refs, const BuildOptions& options) {
  BinaryBvh bvh;
  BinnedSahBuilder(refs, options, bvh).run();
  return bvh;
}

}  // namespace obvh
