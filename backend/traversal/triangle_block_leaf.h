// Testing a leaf stored as TriangleBlock4 groups: the watertight edge functions of four triangles in
// one SIMD pass, then, when a lane passes, the double-precision second half in lanes of double
// (D4), and the lanes' answers visited in lane order (the fast mode's Moeller-Trumbore test runs
// whole in SIMD). Lane order and the same operations per lane make the answers bit-identical to
// testing the triangles one by one (the scalar FloatScalar<4> instantiation is the reference).
// The block tests are always inlined into the traversal that calls them: they are then compiled for
// that kernel's instruction set (VEX-encoded in the AVX2 kernels), not taken from the one baseline
// copy the linker keeps of an instantiation every kernel shares.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

#include "bvh/triangle_block.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

// The watertight test's edge functions U, V, W (weights of v0, v1, v2) for SIMD lanes that are
// four triangles of one ray (blocks) or of each of two rays (triangle_block_pairs.h), in the ray's
// (kx, ky, kz) order and sheared, from the origin relative to each vertex (org - v): the negatives
// of the scalar test's vertices relative to the origin, exactly (rounding is symmetric in sign),
// so that the vertex is the subtraction's memory operand (nine loads a block fewer). U, V and W
// are products of two such values and come out as the scalar test's floats; x, y and dz are the
// negatives of its values.
template <typename F>
struct ShearedEdges {
  F x[3], y[3];  // org - v, sheared: the scalar test's sheared vertex coordinates, negated
  F dz[3];       // org - v along kz (the dominant axis), unsheared
  F U, V, W;
};

// vertex(k, a): the lanes' vertex k along the frame's a-th axis; org: the origin along those axes.
template <typename F, typename Vertex>
[[gnu::always_inline]] inline ShearedEdges<F> shearedEdges(Vertex&& vertex, const F org[3], const F& sx,
                                                           const F& sy) {
  ShearedEdges<F> e;
  for (int k = 0; k < 3; ++k) {
    const F dx = org[0] - vertex(k, 0);
    const F dy = org[1] - vertex(k, 1);
    const F dz = org[2] - vertex(k, 2);
    e.x[k] = dx - sx * dz;
    e.y[k] = dy - sy * dz;
    e.dz[k] = dz;
  }
  e.U = e.x[2] * e.y[1] - e.y[2] * e.x[1];
  e.V = e.x[0] * e.y[2] - e.y[0] * e.x[2];
  e.W = e.x[1] * e.y[0] - e.y[1] * e.x[0];
  return e;
}

// Lanes (of `used`) whose edge functions pass the sign test, to be resolved with their U, V, W, and
// lanes where an edge function rounded to zero, to be tested again with the scalar test's
// double-precision fallback.
struct EdgeVerdict {
  int resolve = 0;
  int recheck = 0;
};

// The masks come from the edge functions' sign bits and their product, instead of nine compares:
// where no value is zero or NaN they say what the compares say. A zero (of either sign) makes the
// product zero, and such lanes are rechecked whatever their signs; so is a lane whose product
// underflows to zero, which the recheck (the scalar test) answers as the resolve path would. A NaN
// answers no hit either way: its sign bit says nothing, and a lane let through to be resolved
// fails finishWatertightHit's U + V + W != 0.
template <typename F>
[[gnu::always_inline]] inline EdgeVerdict judgeEdges(const ShearedEdges<F>& e, int used) {
  const int anyZero = equalMask(e.U * e.V * e.W, F::broadcast(0.f));
  const int mixedSigns = unequalSignsMask(e.U, e.V, e.W);
  EdgeVerdict verdict;
  verdict.recheck = anyZero & used;
  if (verdict.recheck) {
    // Two vertices that coincide in the ray's frame (a wall seen edge-on by a ray parallel to it,
    // as in orthographic views of stacks) make their edge function exactly zero and the other two
    // exact negatives, in float and in the scalar test's double fallback alike: that test rejects
    // the triangle (determinant zero), so such lanes need no recheck.
    const int coincident = (equalMask(e.x[0], e.x[1]) & equalMask(e.y[0], e.y[1])) |
                           (equalMask(e.x[1], e.x[2]) & equalMask(e.y[1], e.y[2])) |
                           (equalMask(e.x[2], e.x[0]) & equalMask(e.y[2], e.y[0]));
    verdict.recheck &= ~coincident;
  }
  verdict.resolve = ~(mixedSigns | anyZero) & used;
  return verdict;
}

// Candidate lanes (edge functions of one sign, none zero) whose plane the ray's line certainly
// crosses before the start of its segment (t < tnear; for tnear = 0, behind the origin), decided in
// float from the edge functions: a secondary ray's start triangle, which Embree rejects in a few
// float instructions, is otherwise resolved in double precision only to be rejected there
// (callgrind, bunny diffuse bounces: 1.08 such passes a ray, about 100 instructions each, of 1,134
// in the kernel; of the lanes the bench's shadow rays, which start on the surface with tnear > 0,
// resolved in double precision on the bunny, 84% were rejected there as lying before tnear).
// Why it is exact: shearing is a linear map of determinant one whatever the rounding of Sx and Sy,
// so with exactly computed edge functions T = U dz0 + V dz1 + W dz2 is -det[v0 - o, v1 - o, v2 - o]
// and U + V + W is -N.(Sx, Sy, 1) for the normal N = (v1 - v0) x (v2 - v0), and the ray's t is
// T / D / dir[kz] for D = N.dir / dir[kz], the exact U + V + W of the exact shear. With R at
// least every |x|, |y|, |dz| and |coordinate of a vertex relative to the origin| (|Sx|, |Sy| <= 1:
// kz is the dominant axis; u = 2^-24): x and y are within 4uR of their exact values, U, V, W
// within 20uR^2 (|U| <= 2R^2), T within 82uR^3, and U + V + W within 70uR^2 of its exact value,
// which lies within 16uR^2 of D (|Sx - dir[kx]/dir[kz]| <= u, |N| components <= 8R^2). The bounds
// used, tBound = 2^-14 R^3 and detBound = 2^-14 R^2 (1024uR^3, 1024uR^2), leave twelve times that.
// Where |U + V + W| > detBound, D has its sign s and |D| > |U + V + W| - detBound; with
// q = s * sign(dir[kz]) * T, t = q' / (|dir[kz]| |D|) for the exact q' < q + tBound. So t < tnear
// wherever q + tBound < tnear |dir[kz]| (|U + V + W| - detBound) (nearAlongKz times the bound on
// |D|), checked with a margin of 2^-20 on each side, more than the rounding of the few float
// operations on either side; for tnear = 0 the test is q < -tBound, the sign of t certainly
// negative. The double-precision second half (errors near 2^-50 of the same
// magnitudes, against a gap of at least eleven twelfths of tBound) then computes t < tnear too
// and rejects the lane. R is kept within [2^-30, 2^36] so that neither bound nor T leaves the
// normal floats, and nearAlongKz must be finite (an overflowed product bounds nothing). (The
// randomized tests find dropped hits only once the bounds are narrowed to 2^-30: they check the
// direction, the bound above the constant.)
// negativeSz: the lanes whose ray has a negative Sz (dir[kz] < 0). nearAlongKz: each lane's ray's
// WatertightRay::nearAlongKz; lanes where it is not positive are tested for t < 0.
template <typename F>
[[gnu::always_inline]] inline int certainlyBeforeNearLanes(const ShearedEdges<F>& e, int negativeSz,
                                                           const F& nearAlongKz, int candidates) {
  const F zero = F::broadcast(0.f);
  // -T, from e.dz = org - v; the same float as T negated.
  const F negT = e.U * e.dz[0] + e.V * e.dz[1] + e.W * e.dz[2];
  // The sign of t = T / det / dir[kz] (Sz = 1 / dir[kz] has dir[kz]'s sign), with U's sign for the
  // determinant's: a candidate's U, V and W share one sign, which their sum keeps. NaNs are dropped
  // below, and so is T = 0 (whose sign bit says nothing).
  const int flip = signMask(e.U) ^ negativeSz;
  const int negative = ~(signMask(negT) ^ flip) & candidates;
  const int startsAhead = lessMask(zero, nearAlongKz) & candidates;  // tnear > 0: positive t may lie before it
  const int considered = negative | startsAhead;
  if (considered == 0) return 0;
  const F det = e.U + e.V + e.W;
  // |dx| <= |x| + |Sx dz| <= |x| + |dz|, and so for dy: an R from the values at hand.
  const F sheared = max(max(max(abs(e.x[0]), abs(e.x[1])), max(abs(e.x[2]), abs(e.y[0]))),
                        max(abs(e.y[1]), abs(e.y[2])));
  const F R = sheared + max(max(abs(e.dz[0]), abs(e.dz[1])), abs(e.dz[2]));
  const F detBound = R * R * F::broadcast(0x1p-14f);
  const F tBound = detBound * R;
  const int usableR = lessEqualMask(F::broadcast(0x1p-30f), R) & lessEqualMask(R, F::broadcast(0x1p36f));
  const int certainDet = lessMask(detBound, abs(det));
  // Rays from tnear = 0 (camera rays, offset secondary rays): t < 0, that is q < -tBound, in fewer
  // operations.
  if (startsAhead == 0) return negative & usableR & certainDet & lessMask(tBound, abs(negT));
  // q + tBound, rounded up by 2^-20 of itself (a rounded sum keeps the exact sum's sign).
  const F q = select(flip, negT, zero - negT);
  const F reach = q + tBound;
  const F reachUp = reach + abs(reach) * F::broadcast(0x1p-20f);
  // tnear |dir[kz]| (|U + V + W| - detBound), rounded down by 2^-20 of itself; 0 (t < 0) for the
  // lanes whose ray starts at its origin, and for an overflowed product, which bounds nothing.
  const F ahead = nearAlongKz * (abs(det) - detBound) * F::broadcast(1.f - 0x1p-20f);
  const int finiteAhead = startsAhead & lessMask(nearAlongKz, F::broadcast(std::numeric_limits<float>::infinity()));
  return considered & usableR & certainDet & lessMask(reachUp, select(finiteAhead, ahead, zero));
}

// A block's four triangles against one ray.
struct BlockCandidates {
  int resolve = 0;
  int recheck = 0;
  alignas(16) float U[4], V[4], W[4];
};

// dropBehind: leave out lanes certainlyBeforeNearLanes finds (for rays with tnear >= 0, which reject them).
template <typename F4>
[[gnu::always_inline]] inline BlockCandidates watertightBlockCandidates(const TriangleBlock4& block,
                                                                        const WatertightRay& wr, bool dropBehind) {
  const F4 org[3] = {F4::broadcast(wr.org[wr.kx]), F4::broadcast(wr.org[wr.ky]), F4::broadcast(wr.org[wr.kz])};
  const int axes[3] = {wr.kx, wr.ky, wr.kz};
  const ShearedEdges<F4> e = shearedEdges(
      [&](int k, int a) __attribute__((always_inline)) { return F4::load(block.v[k][axes[a]]); }, org,
      F4::broadcast(wr.Sx), F4::broadcast(wr.Sy));
  const EdgeVerdict verdict = judgeEdges(e, block.usedLanes());
  BlockCandidates c;
  c.resolve = verdict.resolve;
  c.recheck = verdict.recheck;
  if (c.resolve && dropBehind)
    c.resolve &= ~certainlyBeforeNearLanes(e, std::signbit(wr.Sz) ? 15 : 0, F4::broadcast(wr.nearAlongKz), c.resolve);
  if (c.resolve) {
    e.U.store(c.U);
    e.V.store(c.V);
    e.W.store(c.W);
  }
  return c;
}

// watertightBlockCandidates for two rays at once, ray a in lanes 0-3 and ray b in lanes 4-7 of
// one eight-lane pass (F8): the rays must share the frame's axis order (kx, ky, kz). Each lane
// computes what the four-lane test computes for its ray, so each ray's candidates and U, V, W are
// the same. dropBehindA / B: as watertightBlockCandidates' dropBehind, per ray.
template <typename F8>
[[gnu::always_inline]] inline void watertightBlockCandidatesOfPair(const TriangleBlock4& block,
                                                                   const WatertightRay& a, const WatertightRay& b,
                                                                   bool dropBehindA, bool dropBehindB,
                                                                   BlockCandidates& ca, BlockCandidates& cb) {
  static_assert(F8::kWidth == 8);
  const int axes[3] = {a.kx, a.ky, a.kz};
  F8 org[3];
  for (int i = 0; i < 3; ++i) org[i] = F8::halves(a.org[axes[i]], b.org[axes[i]]);
  const ShearedEdges<F8> e = shearedEdges(
      [&](int k, int i) __attribute__((always_inline)) { return F8::twice(block.v[k][axes[i]]); }, org,
      F8::halves(a.Sx, b.Sx), F8::halves(a.Sy, b.Sy));
  const EdgeVerdict verdict = judgeEdges(e, block.usedLanes() * 0x11);
  int resolve = verdict.resolve;
  const int dropping = resolve & ((dropBehindA ? 0x0F : 0) | (dropBehindB ? 0xF0 : 0));
  if (dropping)
    resolve &= ~certainlyBeforeNearLanes(e, (std::signbit(a.Sz) ? 0x0F : 0) | (std::signbit(b.Sz) ? 0xF0 : 0),
                                         F8::halves(a.nearAlongKz, b.nearAlongKz), dropping);
  ca.resolve = resolve & 15, cb.resolve = resolve >> 4;
  ca.recheck = verdict.recheck & 15, cb.recheck = verdict.recheck >> 4;
  if (resolve) {
    e.U.storeHalves(ca.U, cb.U);
    e.V.storeHalves(ca.V, cb.V);
    e.W.storeHalves(ca.W, cb.W);
  }
}

// A block's four triangles through the whole Moeller-Trumbore test (intersect/moeller_triangle.h,
// the same operations lane by lane): the lanes that hit within the segment as it stood when the
// block was entered, with their answers. The scalar test scales by sgn = sign(den) and divides by
// |den|; rounding is symmetric in sign, so T / den and U / den as computed here are the same floats,
// and the distance test is written as its two sign cases, which is exact.
struct MoellerBlockHits {
  int lanes = 0;
  alignas(16) float T[4], den[4], t[4], u[4], v[4];  // T and den unsigned: dot(Ng, C), dot(Ng, dir)
};

template <typename F4>
[[gnu::always_inline]] inline MoellerBlockHits moellerBlockHits(const TriangleBlock4& block, const Ray& ray) {
  F4 v[3][3];
  for (int vertex = 0; vertex < 3; ++vertex)
    for (int axis = 0; axis < 3; ++axis) v[vertex][axis] = F4::load(block.v[vertex][axis]);
  F4 e1[3], e2[3], C[3], d[3];
  for (int axis = 0; axis < 3; ++axis) {
    e1[axis] = v[0][axis] - v[1][axis];
    e2[axis] = v[2][axis] - v[0][axis];
    C[axis] = v[0][axis] - F4::broadcast(ray.org[axis]);
    d[axis] = F4::broadcast(ray.dir[axis]);
  }
  auto cross = [](const F4* a, const F4* b, F4* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
  };
  auto dot = [](const F4* a, const F4* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  F4 Ng[3], R[3];
  cross(e2, e1, Ng);
  cross(C, d, R);
  const F4 den = dot(Ng, d);
  const F4 U = dot(R, e2), V = dot(R, e1), sum = U + V;
  const F4 zero = F4::broadcast(0.f);
  const int positive = lessMask(zero, den) & lessEqualMask(zero, U) & lessEqualMask(zero, V) & lessEqualMask(sum, den);
  const int negative = lessMask(den, zero) & lessEqualMask(U, zero) & lessEqualMask(V, zero) & lessEqualMask(den, sum);
  MoellerBlockHits hits;
  if (((positive | negative) & block.usedLanes()) == 0) return hits;
  const F4 T = dot(Ng, C);
  const F4 nearLimit = den * F4::broadcast(ray.tnear), farLimit = den * F4::broadcast(ray.tfar);
  const int inPositive = lessMask(nearLimit, T) & lessEqualMask(T, farLimit);
  const int inNegative = lessMask(T, nearLimit) & lessEqualMask(farLimit, T);
  hits.lanes = ((positive & inPositive) | (negative & inNegative)) & block.usedLanes();
  if (hits.lanes == 0) return hits;
  const F4 rcpDen = F4::broadcast(1.f) / den;
  T.store(hits.T);
  den.store(hits.den);
  (T * rcpDen).store(hits.t);
  (U * rcpDen).store(hits.u);
  (V * rcpDen).store(hits.v);
  return hits;
}

// The double-precision second half of the watertight test (planeHitInDouble) for the block's four
// triangles at once, in lanes of D4 (simd/double_lanes.h): each lane's t, u, v are the floats the
// scalar test computes for that triangle. One pass for four lanes costs about what one scalar
// pass did (callgrind: 408 -> 402 instructions a leaf visit on a grid whose rays hit one lane).
struct BlockPlaneHits {
  int degenerate = 0;  // lanes whose edge determinant is zero
  alignas(16) float t[4], u[4], v[4];
};

template <typename D4>
[[gnu::always_inline]] inline BlockPlaneHits blockPlaneHits(const TriangleBlock4& block, const Ray& ray) {
  D4 org[3], dir[3], vertex[3][3];
  for (int a = 0; a < 3; ++a) {
    org[a] = D4::broadcast(ray.org[a]);
    dir[a] = D4::broadcast(ray.dir[a]);
    for (int k = 0; k < 3; ++k) vertex[k][a] = D4::widen(block.v[k][a]);
  }
  const DoublePlaneHit<D4> h = planeHitInDouble(org, dir, vertex[0], vertex[1], vertex[2]);
  BlockPlaneHits hits;
  hits.degenerate = zeroMask(h.det);
  h.t.narrow(hits.t);
  h.u.narrow(hits.u);
  h.v.narrow(hits.v);
  return hits;
}

// A hit on lane `lane` of a block, read from the block's lanes: copying the lane out as a
// StoredTriangle first kept it alive across the double-precision test, in spilled registers.
// Always inlined (with makeTriangleHit): the oriented kernels, whose leaf visitors are inlined into
// the walk, called the one baseline copy the linker keeps for every accepted hit (a call, its
// vzeroupper, the Hit returned through memory); inlined, the stack presets' views traced 5-9%
// faster (drop-in, one thread, three alternations).
[[gnu::always_inline]] inline Hit makeBlockHit(const TriangleSet& set, const TriangleBlock4& block, int lane,
                                               const TriangleHit& th, uint32_t instID) {
  return makeTriangleHit(set, block.vertex(0, lane), block.vertex(1, lane), block.vertex(2, lane), block.geomID[lane],
                         block.primID[lane], TriangleKind(block.kind[lane]), th, instID);
}

// The second half of visitBlockHits' watertight test: each candidate lane of c in lane order, its
// answer from the double-precision plane hit (or the scalar test's recheck); visit(lane, th)
// returns true to stop.
template <typename D4, typename Visit>
[[gnu::always_inline]] inline bool visitBlockCandidates(const TriangleSet& set, const TriangleBlock4& block,
                                                        const BlockCandidates& c, const WatertightRay& wr,
                                                        const Ray& ray, Visit&& visit) {
  BlockPlaneHits plane;
  if (c.resolve) plane = blockPlaneHits<D4>(block, ray);
  int lanes = c.resolve | c.recheck;
  while (lanes) {
    const int lane = __builtin_ctz(unsigned(lanes));
    lanes &= lanes - 1;
    if ((set.geometryMasks[block.geomID[lane]] & ray.mask) == 0) continue;
    TriangleHit th;
    const bool hit =
        (c.recheck >> lane) & 1
            ? intersectWatertight(wr, ray, block.vertex(0, lane), block.vertex(1, lane), block.vertex(2, lane), th)
            : finishWatertightHit(
                  wr, ray, [&](int k, int axis) { return block.v[k][axis][lane]; }, c.U[lane], c.V[lane], c.W[lane],
                  (plane.degenerate >> lane) & 1, plane.t[lane], plane.u[lane], plane.v[lane], th);
    if (hit && visit(lane, th)) return true;
  }
  return false;
}

// Visits each candidate lane of the block in lane order with its triangle test result;
// visit(lane, th) returns true to stop. kDropBehind: candidates certainly before tnear are
// left out in float (certainlyBeforeNearLanes); kernels for rays that start away from surfaces (camera
// rays declared coherent) leave the check out, which costs them about 19 instructions a block with
// candidates (callgrind, bunny camera rays: 1.1% more instructions with it).
template <typename F4, typename D4, bool kDropBehind = true, typename Visit>
[[gnu::always_inline]] inline bool visitBlockHits(const TriangleSet& set, const TriangleBlock4& block, const WatertightRay& wr,
                           const Ray& ray, Visit&& visit) {
  if (set.fast) {
    const MoellerBlockHits hits = moellerBlockHits<F4>(block, ray);
    for (int lanes = hits.lanes; lanes; lanes &= lanes - 1) {
      const int lane = __builtin_ctz(unsigned(lanes));
      if ((set.geometryMasks[block.geomID[lane]] & ray.mask) == 0) continue;
      // The scalar test's T <= |den| * tfar against tfar as an earlier lane may have shrunk it.
      const float den = hits.den[lane], T = hits.T[lane], farLimit = den * ray.tfar;
      if (!(den > 0.f ? T <= farLimit : farLimit <= T)) continue;
      if (visit(lane, TriangleHit{hits.t[lane], hits.u[lane], hits.v[lane]})) return true;
    }
    return false;
  }
  // A NaN tnear rejects every t as well.
  return visitBlockCandidates<D4>(set, block, watertightBlockCandidates<F4>(block, wr, kDropBehind && !(ray.tnear < 0.f)),
                                  wr, ray, visit);
}

// The closest-hit visit of a block's candidates for one ray: an accepted hit shrinks ray.tfar and
// becomes `hit`, found is set. Inlined (GCC kept the lambda out of line: a call with vzeroupper for
// every accepted hit).
[[gnu::always_inline]] inline auto closestHitVisitor(const TriangleSet& set, const TriangleBlock4& block, Ray& ray,
                                                     Hit& hit, const QueryState& state, bool& found) {
  return [&set, &block, &ray, &hit, &state, &found](int lane, const TriangleHit& th) __attribute__((always_inline)) {
    if (needsFilter(set.intersectFiltered, block.geomID[lane], state) &&
        !state.callbacks->acceptHit(set.owner, ray, makeBlockHit(set, block, lane, th, state.instID), th.t, false))
      return false;
    ray.tfar = th.t;
    hit = makeBlockHit(set, block, lane, th, state.instID);
    found = true;
    return false;
  };
}

// The any-hit visit of a block's candidates for one ray: true (stop) when the filters accept one.
[[gnu::always_inline]] inline auto anyHitVisitor(const TriangleSet& set, const TriangleBlock4& block, const Ray& ray,
                                                 const QueryState& state) {
  return [&set, &block, &ray, &state](int lane, const TriangleHit& th) {
    return !needsFilter(set.occlusionFiltered, block.geomID[lane], state) ||
           state.callbacks->acceptHit(set.owner, ray, makeBlockHit(set, block, lane, th, state.instID), th.t, true);
  };
}

// Closest-hit test of blockCount blocks from firstBlock; shrinks ray.tfar on accepted hits.
// kDropBehind: see visitBlockHits.
template <typename F4, typename D4, bool kDropBehind = true>
[[gnu::always_inline]] inline bool intersectBlocksClosest(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                                   uint32_t blockCount, const WatertightRay& wr, Ray& ray, Hit& hit,
                                   const QueryState& state) {
  bool found = false;
  for (uint32_t b = firstBlock; b < firstBlock + blockCount; ++b)
    visitBlockHits<F4, D4, kDropBehind>(set, blocks[b], wr, ray, closestHitVisitor(set, blocks[b], ray, hit, state, found));
  return found;
}

// True when any triangle of the blocks blocks the ray (and the filters accept it).
template <typename F4, typename D4>
[[gnu::always_inline]] inline bool intersectBlocksAny(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                               uint32_t blockCount, const WatertightRay& wr, const Ray& ray, const QueryState& state) {
  for (uint32_t b = firstBlock; b < firstBlock + blockCount; ++b)
    if (visitBlockHits<F4, D4>(set, blocks[b], wr, ray, anyHitVisitor(set, blocks[b], ray, state))) return true;
  return false;
}

}  // namespace obvh
