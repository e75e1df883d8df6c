#include "traversal/oriented_wide_traversal.h"

#include <cmath>
#include <limits>

#include "simd/float4_sse.h"
#include "traversal/box_test.h"
#include "traversal/oriented_box_test.h"
#include "traversal/triangle_block_leaf.h"

namespace obvh {
namespace {

using F = simd::Float4Sse;
using Codes = OrientedWideNode::Codes;

struct OrientedWideRay {
  F org[3], dir[3];
  F originNorm;
  explicit OrientedWideRay(const Ray& ray) {
    for (int a = 0; a < 3; ++a) org[a] = F::broadcast(ray.org[a]), dir[a] = F::broadcast(ray.dir[a]);
    originNorm = F::broadcast(std::fabs(ray.org.x) + std::fabs(ray.org.y) + std::fabs(ray.org.z));
  }
};

// The children the ray enters within [tnear, tfar], with their entry distances. Per child as in
// OrientedRay::enter: the transformed ray against the box widened by the transform's rounding
// margin (zero for axis-aligned children, whose identity rows transform exactly). A ray that does
// not move along a frame axis (1/dir infinite) gets -inf..+inf from a slab that holds its origin
// and an empty interval from one that does not; an origin exactly on a plane makes that plane's
// distance 0 * inf = NaN, replaced by the value that leaves the slab unbounded on that side
// (-1/dir for the lower plane, 1/dir for the upper), so the ray counts as inside, as in the
// scalar box test.
[[gnu::always_inline]] inline int enterChildren(const OrientedWideNode& node, const OrientedWideRay& r, float tnear, float tfar, float entry[4]) {
  const F margin = F::load(node.oriented) * F::broadcast(2.f * kObbMarginScale) * (r.originNorm + F::load(node.magnitude));
  F nearT = F::broadcast(tnear), farT = F::broadcast(std::numeric_limits<float>::infinity());
  for (int row = 0; row < 3; ++row) {
    const F a0 = F::load(node.axis[row][0]), a1 = F::load(node.axis[row][1]), a2 = F::load(node.axis[row][2]);
    const F o = a0 * r.org[0] + a1 * r.org[1] + a2 * r.org[2];
    const F d = a0 * r.dir[0] + a1 * r.dir[1] + a2 * r.dir[2];
    const F inv = F::broadcast(1.f) / d;
    const F t0 = replaceNaN((F::load(node.lower[row]) - margin - o) * inv, F::broadcast(0.f) - inv);
    const F t1 = replaceNaN((F::load(node.upper[row]) + margin - o) * inv, inv);
    nearT = max(min(t0, t1), nearT);
    farT = min(max(t0, t1), farT);
  }
  farT = min(farT * F::broadcast(kConservativeFarScale), F::broadcast(tfar));
  nearT.store(entry);
  return lessEqualMask(nearT, farT) & node.usedMask;
}

struct Pending {
  uint32_t child;
  float t;
};

// leafVisitor(firstBlock, blockCount) returns true to stop. Closest-hit queries visit children near
// to far and skip pending ones entered beyond the (shrinking) tfar.
template <bool kNearToFar, typename LeafVisitor>
void traverseOrientedWide(const OrientedWideBvh& bvh, const Ray& ray, TraversalCounters* counters,
                          LeafVisitor&& leafVisitor) {
  if (bvh.empty()) return;
  const OrientedWideRay r(ray);
  Pending stack[3 * 128];
  int top = 0;
  alignas(16) float entry[4];
  uint32_t current = bvh.rootChild;
  for (;;) {
    bool descended = false;
    if (Codes::isLeaf(current)) {
      if (counters) ++counters->leafVisits;
      if (leafVisitor(Codes::leafFirstBlock(current), Codes::leafBlockCount(current))) return;
    } else {
      const OrientedWideNode& node = bvh.nodes[current];
      if (counters) counters->obbTests += uint64_t(__builtin_popcount(unsigned(node.usedMask)));
      int mask = enterChildren(node, r, ray.tnear, ray.tfar, entry);
      if (mask) {
        Pending entered[4];
        int n = 0;
        for (; mask; mask &= mask - 1) {
          const int lane = __builtin_ctz(unsigned(mask));
          Pending p{node.child[lane], entry[lane]};
          int k = n++;
          while (kNearToFar && k > 0 && entered[k - 1].t > p.t) {
            entered[k] = entered[k - 1];
            --k;
          }
          entered[k] = p;
        }
        for (int k = n - 1; k >= 1; --k) stack[top++] = entered[k];
        current = entered[0].child;
        descended = true;
      }
    }
    if (descended) continue;
    for (;;) {
      if (top == 0) return;
      const Pending p = stack[--top];
      if (p.t > ray.tfar) continue;
      current = p.child;
      break;
    }
  }
}

}  // namespace

bool intersectClosestOrientedWide(const TriangleOrientedWideView& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters) {
  const WatertightRay wr(ray);
  const TriangleBlock4* blocks = view.bvh->blocks.data();
  bool found = false;
  traverseOrientedWide<true>(*view.bvh, ray, counters, [&](uint32_t firstBlock, uint32_t blockCount) {
    found |= intersectBlocksClosest<F>(view.set, blocks, firstBlock, blockCount, wr, ray, hit, state);
    return false;
  });
  return found;
}

bool intersectAnyOrientedWide(const TriangleOrientedWideView& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters) {
  const WatertightRay wr(ray);
  const TriangleBlock4* blocks = view.bvh->blocks.data();
  bool found = false;
  traverseOrientedWide<false>(*view.bvh, ray, counters, [&](uint32_t firstBlock, uint32_t blockCount) {
    found = intersectBlocksAny<F>(view.set, blocks, firstBlock, blockCount, wr, ray, state);
    return found;
  });
  return found;
}

}  // namespace obvh
