// The leaf blocks' test against the scalar watertight test, where the block test computes something
// its own way: the segment ends checked against the double-precision second half computed for four
// lanes at once.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "math/float_steps.h"
#include "simd/cpu_features.h"
#include "simd/double_lanes.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "traversal/triangle_block_leaf.h"

namespace obvh {
namespace {

// Every lane's answer (lane order) of a block against one ray, as the kernels' leaf test gives it.
struct LaneAnswer {
  int lane;
  TriangleHit hit;
};

template <typename F4, typename D4>
[[gnu::always_inline]] inline std::vector<LaneAnswer> laneAnswers(const TriangleBlock4& block, const Ray& ray) {
  static const uint32_t allMasks[1] = {0xFFFFFFFFu};
  TriangleSet set;
  set.geometryMasks = allMasks;
  std::vector<LaneAnswer> answers;
  visitBlockHits<F4, D4>(set, block, WatertightRay(ray), ray, [&](int lane, const TriangleHit& th) {
    answers.push_back({lane, th});
    return false;
  });
  return answers;
}

std::vector<LaneAnswer> sseLaneAnswers(const TriangleBlock4& block, const Ray& ray) {
  return laneAnswers<simd::Float4Sse, simd::Double4Sse>(block, ray);
}
std::vector<LaneAnswer> scalarLaneAnswers(const TriangleBlock4& block, const Ray& ray) {
  return laneAnswers<simd::Float4Scalar, simd::Double4Scalar>(block, ray);
}

}  // namespace
}  // namespace obvh

// The AVX lanes in a function compiled for AVX2 (no vector value crosses between targets).
#pragma GCC push_options
#pragma GCC target("avx2")
#include "simd/double4_avx.h"
namespace obvh {
namespace {
std::vector<LaneAnswer> avxLaneAnswers(const TriangleBlock4& block, const Ray& ray) {
  return laneAnswers<simd::Float4Sse, simd::Double4Avx>(block, ray);
}
}  // namespace
}  // namespace obvh
#pragma GCC pop_options

namespace obvh {
namespace {

struct BlockAnswer {
  bool hit = false;
  float t = 0.f;
};

BlockAnswer firstAnswer(const std::vector<LaneAnswer>& answers) {
  if (answers.empty()) return {};
  EXPECT_EQ(answers[0].lane, 0);
  return {true, answers[0].hit.t};
}

Vec3f randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> normal;
  for (;;) {
    const Vec3f d{normal(rng), normal(rng), normal(rng)};
    const float length = std::sqrt(dot(d, d));
    if (length > 1e-3f) return d * (1.f / length);
  }
}

// Rays aimed at vertices, edges and interiors of triangles near and far from the origin, small and
// large, seen from near and far; the segment ends exactly at the scalar test's hit distance and
// one float before it: the block test hits exactly where the scalar test does, at the same t. (It
// caught the distance cull that once dropped lanes before the second half when the cull had no
// slack for a hit at the nearest vertex, whose rounded distance can exceed t.)
TEST(TriangleBlockLeaf, SegmentEndsAnswerLikeTheScalarTest) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const float offsets[] = {0.f, 1e3f, 1e5f, 1e6f};
  const float sizes[] = {1e-3f, 1.f, 100.f};
  const float distances[] = {1e-2f, 1.f, 1e3f};
  const float aims[][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5f, 0.5f, 0}, {0, 0.5f, 0.5f}, {0.2f, 0.3f, 0.5f}};
  int hitsChecked = 0;
  for (float offset : offsets)
    for (float size : sizes)
      for (float distance : distances)
        for (const auto& aim : aims)
          for (int trial = 0; trial < 8; ++trial) {
            const Vec3f center = randomUnit(rng) * offset;
            StoredTriangle tri;
            tri.v0 = center + randomUnit(rng) * size;
            tri.v1 = center + randomUnit(rng) * size;
            tri.v2 = center + randomUnit(rng) * (size * (0.5f + unit(rng)));
            const Vec3f target = tri.v0 * aim[0] + tri.v1 * aim[1] + tri.v2 * aim[2];
            Ray ray;
            ray.dir = randomUnit(rng);
            ray.org = target - ray.dir * distance;
            ray.tfar = std::numeric_limits<float>::infinity();
            TriangleHit exact;
            if (!intersectWatertight(WatertightRay(ray), ray, tri.v0, tri.v1, tri.v2, exact)) continue;
            ++hitsChecked;
            TriangleBlock4 block;
            block.fill(&tri, 1);
            for (int ends = 0; ends < 3; ++ends) {
              Ray segment = ray;
              if (ends == 0) segment.tfar = exact.t;  // ends at the hit: hits
              if (ends == 1) segment.tnear = nextFloatDown(exact.t), segment.tfar = exact.t;  // one float wide: hits
              if (ends == 2) segment.tfar = nextFloatDown(exact.t);  // ends before the hit: misses
              TriangleHit scalar;
              const bool scalarHit = intersectWatertight(WatertightRay(segment), segment, tri.v0, tri.v1, tri.v2, scalar);
              ASSERT_EQ(scalarHit, ends != 2);
              const BlockAnswer sse = firstAnswer(sseLaneAnswers(block, segment));
              const BlockAnswer reference = firstAnswer(scalarLaneAnswers(block, segment));
              EXPECT_EQ(sse.hit, scalarHit) << "offset " << offset << " size " << size << " distance " << distance;
              EXPECT_EQ(reference.hit, scalarHit);
              if (scalarHit && sse.hit) {
                EXPECT_EQ(sse.t, scalar.t);
              }
            }
          }
  EXPECT_GT(hitsChecked, 500);
}

// The double-precision second half of four lanes at once (Double4Scalar, Double4Sse, Double4Avx)
// answers each lane exactly as the scalar test answers its triangle: same lanes, t, u and v, on
// blocks of four triangles near each other (a ray passes through several) near and far from the
// origin, small and large, and with degenerate lanes (a repeated vertex, collinear vertices).
TEST(TriangleBlockLeaf, DoublePrecisionLanesAnswerLikeTheScalarTest) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const bool avx2 = simd::cpuHasAvx2();
  size_t lanesHit = 0, degenerateLanes = 0;
  for (float offset : {0.f, 10.f, 1e4f, 1e6f})
    for (float size : {1e-3f, 1.f, 100.f})
      for (int trial = 0; trial < 400; ++trial) {
        const Vec3f center = randomUnit(rng) * offset;
        StoredTriangle tris[4];
        for (StoredTriangle& tri : tris) {
          tri.v0 = center + randomUnit(rng) * size;
          tri.v1 = center + randomUnit(rng) * size;
          tri.v2 = center + randomUnit(rng) * size;
        }
        if (trial % 5 == 0) tris[trial % 4].v2 = tris[trial % 4].v1;  // zero area
        if (trial % 7 == 0) tris[(trial + 1) % 4].v2 = tris[(trial + 1) % 4].v0 * 2.f - tris[(trial + 1) % 4].v1;
        TriangleBlock4 block;
        block.fill(tris, 4);
        Ray ray;
        ray.dir = randomUnit(rng);
        ray.org = center - ray.dir * (size * (1.f + 4.f * unit(rng))) + randomUnit(rng) * (0.3f * size);
        ray.tfar = std::numeric_limits<float>::infinity();
        const WatertightRay wr(ray);
        std::vector<LaneAnswer> expected;
        for (int lane = 0; lane < 4; ++lane) {
          TriangleHit th;
          if (intersectWatertight(wr, ray, tris[lane].v0, tris[lane].v1, tris[lane].v2, th)) expected.push_back({lane, th});
        }
        lanesHit += expected.size();
        for (const StoredTriangle& tri : tris) degenerateLanes += dot(cross(tri.v1 - tri.v0, tri.v2 - tri.v0), cross(tri.v1 - tri.v0, tri.v2 - tri.v0)) == 0.f;
        std::vector<std::vector<LaneAnswer>> answers = {scalarLaneAnswers(block, ray), sseLaneAnswers(block, ray)};
        if (avx2) answers.push_back(avxLaneAnswers(block, ray));
        for (size_t kind = 0; kind < answers.size(); ++kind) {
          ASSERT_EQ(answers[kind].size(), expected.size()) << "lane type " << kind << " offset " << offset << " size " << size;
          for (size_t i = 0; i < expected.size(); ++i) {
            EXPECT_EQ(answers[kind][i].lane, expected[i].lane);
            EXPECT_EQ(answers[kind][i].hit.t, expected[i].hit.t) << "lane type " << kind;
            EXPECT_EQ(answers[kind][i].hit.u, expected[i].hit.u) << "lane type " << kind;
            EXPECT_EQ(answers[kind][i].hit.v, expected[i].hit.v) << "lane type " << kind;
          }
        }
      }
  EXPECT_GT(lanesHit, 2000u);
  EXPECT_GT(degenerateLanes, 300u);
}

}  // namespace
}  // namespace obvh
