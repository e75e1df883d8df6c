// Two of a packet's rays against a leaf block in one eight-lane pass (triangle_block_pairs.h)
// against each ray tested alone with the four-lane block test: the same candidate lanes, rechecks
// and edge functions bit for bit, and through a whole leaf the same closest hits (t, u, v, Ng, ids)
// and the same occluded rays. The eight-lane type is the scalar reference (FloatScalar<8>) and,
// where the CPU has AVX2, Float8Avx.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "float_bits.h"
#include "random_directions.h"
#include "simd/cpu_features.h"
#include "simd/double_lanes.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "traversal/triangle_block_pairs.h"

namespace obvh {
namespace {

struct PairCandidates {
  BlockCandidates a, b;
};

// Always inlined, so that each ISA's test is compiled for that ISA (see the AVX2 region below).
template <typename F8>
[[gnu::always_inline]] inline PairCandidates pairCandidatesOf(const TriangleBlock4& block, const WatertightRay& a,
                                                              const WatertightRay& b, bool dropA, bool dropB) {
  PairCandidates c;
  watertightBlockCandidatesOfPair<F8>(block, a, b, dropA, dropB, c.a, c.b);
  return c;
}

// A leaf's closest hits and occluded rays for the rays of `mask`, pairs or not.
struct LeafAnswers {
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  uint32_t found = 0, blocked = 0;
};

template <typename F4, typename F8, typename D4>
[[gnu::always_inline]] inline LeafAnswers leafAnswersOf(const TriangleSet& set, const std::vector<TriangleBlock4>& blocks,
                                                        std::vector<Ray> rays, uint32_t mask, bool dropBehind) {
  std::vector<WatertightRay> frames;
  for (const Ray& ray : rays) frames.emplace_back(ray);
  const auto frameOf = [&](int r) -> const WatertightRay& { return frames[size_t(r)]; };
  const QueryState state;
  LeafAnswers out;
  out.hits.resize(rays.size());
  const uint32_t count = uint32_t(blocks.size());
  out.blocked = intersectBlocksAnyOfRays<F4, F8, D4>(set, blocks.data(), 0, count, frameOf, rays.data(), mask, state);
  out.found = dropBehind ? intersectBlocksClosestOfRays<F4, F8, D4, true>(set, blocks.data(), 0, count, frameOf,
                                                                          rays.data(), out.hits.data(), mask, state)
                         : intersectBlocksClosestOfRays<F4, F8, D4, false>(set, blocks.data(), 0, count, frameOf,
                                                                           rays.data(), out.hits.data(), mask, state);
  out.rays = rays;
  return out;
}

PairCandidates scalarPair(const TriangleBlock4& block, const WatertightRay& a, const WatertightRay& b, bool dropA,
                          bool dropB) {
  return pairCandidatesOf<simd::FloatScalar<8>>(block, a, b, dropA, dropB);
}
LeafAnswers scalarPairsLeaf(const TriangleSet& set, const std::vector<TriangleBlock4>& blocks, const std::vector<Ray>& rays,
                            uint32_t mask, bool dropBehind) {
  return leafAnswersOf<simd::Float4Scalar, simd::FloatScalar<8>, simd::Double4Scalar>(set, blocks, rays, mask,
                                                                                       dropBehind);
}
// Every ray alone: the reference.
LeafAnswers aloneLeaf(const TriangleSet& set, const std::vector<TriangleBlock4>& blocks, const std::vector<Ray>& rays,
                      uint32_t mask, bool dropBehind) {
  return leafAnswersOf<simd::Float4Scalar, void, simd::Double4Scalar>(set, blocks, rays, mask, dropBehind);
}

}  // namespace
}  // namespace obvh

// The eight-wide lanes in functions compiled for AVX2 (no vector value crosses between targets).
#pragma GCC push_options
#pragma GCC target("avx2")
#include "simd/double4_avx.h"
#include "simd/float8_avx.h"
namespace obvh {
namespace {
PairCandidates avxPair(const TriangleBlock4& block, const WatertightRay& a, const WatertightRay& b, bool dropA,
                       bool dropB) {
  return pairCandidatesOf<simd::Float8Avx>(block, a, b, dropA, dropB);
}
LeafAnswers avxPairsLeaf(const TriangleSet& set, const std::vector<TriangleBlock4>& blocks, const std::vector<Ray>& rays,
                         uint32_t mask, bool dropBehind) {
  return leafAnswersOf<simd::Float4Sse, simd::Float8Avx, simd::Double4Avx>(set, blocks, rays, mask, dropBehind);
}
}  // namespace
}  // namespace obvh
#pragma GCC pop_options

namespace obvh {
namespace {

using test::sameBits;
using test::randomUnit;

// Triangles of a small mesh patch: vertices on an integer grid (rays through grid points meet edge
// functions that are exactly zero, which the block test sends to the recheck), shared edges, now
// and then a degenerate triangle, scaled and moved away from the origin.
std::vector<StoredTriangle> patchTriangles(std::mt19937& rng, int count, float scale, const Vec3f& offset) {
  std::uniform_int_distribution<int> grid(-3, 3);
  std::vector<StoredTriangle> tris;
  Vec3f previous[2] = {{0, 0, 0}, {1, 0, 0}};
  for (int i = 0; i < count; ++i) {
    const Vec3f fresh{float(grid(rng)), float(grid(rng)), float(grid(rng)) * 0.25f};
    StoredTriangle tri;
    tri.v0 = offset + previous[0] * scale;
    tri.v1 = offset + previous[1] * scale;
    tri.v2 = offset + fresh * scale;
    if (i % 9 == 4) tri.v2 = tri.v1;  // zero area
    tri.geomID = 0;
    tri.primID = uint32_t(i);
    tris.push_back(tri);
    previous[0] = previous[1];
    previous[1] = fresh;
  }
  return tris;
}

std::vector<TriangleBlock4> blocksOf(const std::vector<StoredTriangle>& tris) {
  std::vector<TriangleBlock4> blocks((tris.size() + 3) / 4);
  for (size_t b = 0; b < blocks.size(); ++b) blocks[b].fill(tris, 4 * b, int(std::min<size_t>(4, tris.size() - 4 * b)));
  return blocks;
}

// Eight rays at the patch: from one origin (a camera's) or from origins spread around it (shadow
// rays from neighbouring hits), through grid points, along axes, some pointing away (the patch
// behind their origin), and with tnear 0, positive or negative.
std::vector<Ray> patchRays(std::mt19937& rng, int trial, float scale, const Vec3f& offset) {
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  std::uniform_int_distribution<int> grid(-3, 3);
  const Vec3f eye = offset + Vec3f{0.3f, -0.2f, 6.f} * scale + randomUnit(rng) * (0.5f * scale);
  std::vector<Ray> rays(8);
  for (int r = 0; r < 8; ++r) {
    Ray& ray = rays[size_t(r)];
    ray.org = trial % 2 ? eye : eye + randomUnit(rng) * (0.5f * scale);
    Vec3f target = offset + Vec3f{unit(rng) * 3.f, unit(rng) * 3.f, unit(rng)} * scale;
    if ((trial + r) % 3 == 0) target = offset + Vec3f{float(grid(rng)), float(grid(rng)), 0.f} * scale;
    if (trial % 5 == 0 && r % 2 == 0) ray.org = Vec3f{target.x, target.y, ray.org.z};  // along -z exactly
    ray.dir = target - ray.org;
    if ((trial + r / 2) % 6 == 5) ray.dir = ray.org - target;  // away: the patch lies behind the origin
    if (trial % 7 == 3 && r == 5) ray.dir = Vec3f{ray.dir.z, ray.dir.y, ray.dir.x};  // another axis order
    ray.tnear = (trial + r) % 4 == 1 ? 0.5f : (trial + r) % 4 == 2 ? -1.f : 0.f;
    ray.tfar = (trial + r) % 5 == 4 ? 0.9f : std::numeric_limits<float>::infinity();
  }
  return rays;
}

// Each half of the eight-lane pass finds what its ray finds alone: the same resolve and recheck
// lanes, the same U, V, W floats on the lanes to resolve, with and without the drop of candidates
// behind the origin. The patches produce rechecks (grid points) and drops (negative tnear is not
// dropped; origins above the patch see some triangles behind).
TEST(TriangleBlockPairs, EachHalfFindsTheCandidatesItsRayFindsAlone) {
  std::mt19937 rng(1130);
  size_t compared = 0, resolveLanes = 0, recheckLanes = 0, droppedLanes = 0;
  for (float offset : {0.f, 50.f, 1e4f})
    for (float scale : {1e-3f, 1.f, 30.f})
      for (int trial = 0; trial < 120; ++trial) {
        const Vec3f shift = randomUnit(rng) * offset;
        const std::vector<TriangleBlock4> blocks = blocksOf(patchTriangles(rng, 1 + trial % 12, scale, shift));
        const std::vector<Ray> rays = patchRays(rng, trial, scale, shift);
        for (int pair = 0; pair < 4; ++pair) {
          const Ray& rayA = rays[size_t(2 * pair)];
          const Ray& rayB = rays[size_t(2 * pair + 1)];
          const WatertightRay a(rayA), b(rayB);
          if (!sameAxisOrder(a, b)) continue;
          for (const TriangleBlock4& block : blocks)
            for (int drop = 0; drop < 4; ++drop) {
              const bool dropA = drop & 1, dropB = drop & 2;
              const BlockCandidates aloneA = watertightBlockCandidates<simd::Float4Scalar>(block, a, dropA);
              const BlockCandidates aloneB = watertightBlockCandidates<simd::Float4Scalar>(block, b, dropB);
              if (drop == 0) {
                resolveLanes += size_t(__builtin_popcount(unsigned(aloneA.resolve | aloneB.resolve)));
                recheckLanes += size_t(__builtin_popcount(unsigned(aloneA.recheck | aloneB.recheck)));
              }
              if (drop == 3) {
                droppedLanes += size_t(__builtin_popcount(unsigned(
                    watertightBlockCandidates<simd::Float4Scalar>(block, a, false).resolve & ~aloneA.resolve)));
              }
              std::vector<PairCandidates> pairs = {scalarPair(block, a, b, dropA, dropB)};
              if (simd::cpuHasAvx2()) pairs.push_back(avxPair(block, a, b, dropA, dropB));
              for (size_t kind = 0; kind < pairs.size(); ++kind) {
                const std::string where = "lane type " + std::to_string(kind) + ", trial " + std::to_string(trial);
                const BlockCandidates* halves[2] = {&pairs[kind].a, &pairs[kind].b};
                const BlockCandidates* alone[2] = {&aloneA, &aloneB};
                for (int h = 0; h < 2; ++h) {
                  ASSERT_EQ(halves[h]->resolve, alone[h]->resolve) << where << ", ray " << h;
                  ASSERT_EQ(halves[h]->recheck, alone[h]->recheck) << where << ", ray " << h;
                  for (int lane = 0; lane < 4; ++lane) {
                    if (!((alone[h]->resolve >> lane) & 1)) continue;
                    EXPECT_TRUE(sameBits(halves[h]->U[lane], alone[h]->U[lane])) << where;
                    EXPECT_TRUE(sameBits(halves[h]->V[lane], alone[h]->V[lane])) << where;
                    EXPECT_TRUE(sameBits(halves[h]->W[lane], alone[h]->W[lane])) << where;
                  }
                }
              }
              ++compared;
            }
        }
      }
  std::printf("compared %zu, lanes to resolve %zu, to recheck %zu, dropped %zu\n", compared, resolveLanes,
              recheckLanes, droppedLanes);
  EXPECT_GT(compared, 10000u);
  EXPECT_GT(resolveLanes, 2000u);
  EXPECT_GT(recheckLanes, 50u);
  EXPECT_GT(droppedLanes, 20u);
}

// Through whole leaves of one to three blocks, the rays of a mask (pairs, a ray left over, a ray of
// another axis order) get the closest hits and occlusion answers each ray gets alone, bit for bit.
TEST(TriangleBlockPairs, LeafAnswersAreEachRaysOwn) {
  std::mt19937 rng(3011);
  std::uniform_int_distribution<uint32_t> masks(1, 255);
  static const uint32_t allMasks[1] = {0xFFFFFFFFu};
  TriangleSet set;
  set.geometryMasks = allMasks;
  size_t raysHit = 0, raysBlocked = 0, compared = 0, pairs = 0;
  for (float offset : {0.f, 1e4f})
    for (float scale : {1e-2f, 1.f, 30.f})
      for (int trial = 0; trial < 300; ++trial) {
        const Vec3f shift = randomUnit(rng) * offset;
        const std::vector<TriangleBlock4> blocks = blocksOf(patchTriangles(rng, 1 + trial % 12, scale, shift));
        const std::vector<Ray> rays = patchRays(rng, trial, scale, shift);
        const uint32_t mask = masks(rng);
        const bool dropBehind = trial % 3 != 0;
        const LeafAnswers expected = aloneLeaf(set, blocks, rays, mask, dropBehind);
        std::vector<WatertightRay> frames(rays.begin(), rays.end());
        forRaysInPairs<simd::FloatScalar<8>>(  // the pairs the leaf tests form
            mask, true, [&](int r) -> const WatertightRay& { return frames[size_t(r)]; },
            [&](int, int, const WatertightRay&, const WatertightRay&) { ++pairs; },
            [](int, const WatertightRay&) {});
        raysHit += size_t(__builtin_popcount(expected.found));
        raysBlocked += size_t(__builtin_popcount(expected.blocked));
        std::vector<LeafAnswers> answers = {scalarPairsLeaf(set, blocks, rays, mask, dropBehind)};
        if (simd::cpuHasAvx2()) answers.push_back(avxPairsLeaf(set, blocks, rays, mask, dropBehind));
        for (size_t kind = 0; kind < answers.size(); ++kind) {
          const std::string where = "lane type " + std::to_string(kind) + ", trial " + std::to_string(trial);
          ASSERT_EQ(answers[kind].found, expected.found) << where;
          ASSERT_EQ(answers[kind].blocked, expected.blocked) << where;
          for (uint32_t m = expected.found; m; m &= m - 1) {
            const size_t r = size_t(__builtin_ctz(m));
            const Hit& got = answers[kind].hits[r];
            const Hit& want = expected.hits[r];
            EXPECT_TRUE(sameBits(answers[kind].rays[r].tfar, expected.rays[r].tfar)) << where << ", ray " << r;
            EXPECT_TRUE(sameBits(got.u, want.u) && sameBits(got.v, want.v)) << where << ", ray " << r;
            EXPECT_TRUE(sameBits(got.Ng.x, want.Ng.x) && sameBits(got.Ng.y, want.Ng.y) && sameBits(got.Ng.z, want.Ng.z))
                << where << ", ray " << r;
            EXPECT_EQ(got.primID, want.primID) << where << ", ray " << r;
            EXPECT_EQ(got.geomID, want.geomID) << where << ", ray " << r;
          }
        }
        ++compared;
      }
  std::printf("pairs %zu, rays hit %zu, blocked %zu\n", pairs, raysHit, raysBlocked);
  EXPECT_EQ(compared, 1800u);
  EXPECT_GT(pairs, 2000u);
  EXPECT_GT(raysHit, 1000u);
  EXPECT_GT(raysBlocked, 1000u);
}

}  // namespace
}  // namespace obvh
