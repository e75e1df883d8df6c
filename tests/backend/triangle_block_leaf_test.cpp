// The leaf blocks' test against the scalar watertight test, where the block test computes something
// its own way: the segment ends checked against the double-precision second half computed for four
// lanes at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "math/float_steps.h"
#include "random_directions.h"
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

using test::randomUnit;

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
            block.fill(&tri, 0, 1);
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

// The scalar watertight test's answers for the block's four triangles, lane by lane.
std::vector<LaneAnswer> scalarTestAnswers(const StoredTriangle tris[4], const Ray& ray) {
  const WatertightRay wr(ray);
  std::vector<LaneAnswer> expected;
  for (int lane = 0; lane < 4; ++lane) {
    TriangleHit th;
    if (intersectWatertight(wr, ray, tris[lane].v0, tris[lane].v1, tris[lane].v2, th)) expected.push_back({lane, th});
  }
  return expected;
}

// Every lane type's block test (scalar, SSE, and AVX where the CPU has it) answers as `expected`.
void expectEveryLaneTypeAnswers(const TriangleBlock4& block, const Ray& ray, const std::vector<LaneAnswer>& expected,
                                const std::string& context) {
  std::vector<std::vector<LaneAnswer>> answers = {scalarLaneAnswers(block, ray), sseLaneAnswers(block, ray)};
  if (simd::cpuHasAvx2()) answers.push_back(avxLaneAnswers(block, ray));
  for (size_t kind = 0; kind < answers.size(); ++kind) {
    ASSERT_EQ(answers[kind].size(), expected.size()) << "lane type " << kind << ", " << context;
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(answers[kind][i].lane, expected[i].lane);
      EXPECT_EQ(answers[kind][i].hit.t, expected[i].hit.t) << "lane type " << kind;
      EXPECT_EQ(answers[kind][i].hit.u, expected[i].hit.u) << "lane type " << kind;
      EXPECT_EQ(answers[kind][i].hit.v, expected[i].hit.v) << "lane type " << kind;
    }
  }
}

// The block's lanes to resolve without the drop of candidates before tnear (all) and with it
// (kept), for the scalar lanes (kind 0) or SSE's (kind 1), after checking that the drop only
// removes lanes and never one of `expected` (the scalar test's hits); context names the case.
struct DropOutcome {
  int all = 0, kept = 0;
  int dropped() const { return all & ~kept; }
};
DropOutcome dropOutcome(const TriangleBlock4& block, const WatertightRay& wr, int kind,
                        const std::vector<LaneAnswer>& expected, const std::string& context) {
  DropOutcome o;
  o.kept = kind == 0 ? watertightBlockCandidates<simd::Float4Scalar>(block, wr, true).resolve
                     : watertightBlockCandidates<simd::Float4Sse>(block, wr, true).resolve;
  o.all = kind == 0 ? watertightBlockCandidates<simd::Float4Scalar>(block, wr, false).resolve
                    : watertightBlockCandidates<simd::Float4Sse>(block, wr, false).resolve;
  EXPECT_EQ(o.kept & ~o.all, 0) << context;
  for (const LaneAnswer& answer : expected)
    EXPECT_FALSE((o.dropped() >> answer.lane) & 1)
        << "a lane the scalar test hits was dropped (t " << answer.hit.t << "): " << context;
  return o;
}

// The double-precision second half of four lanes at once (Double4Scalar, Double4Sse, Double4Avx)
// answers each lane exactly as the scalar test answers its triangle: same lanes, t, u and v, on
// blocks of four triangles near each other (a ray passes through several) near and far from the
// origin, small and large, and with degenerate lanes (a repeated vertex, collinear vertices).
TEST(TriangleBlockLeaf, DoublePrecisionLanesAnswerLikeTheScalarTest) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
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
        block.fill(tris, 0, 4);
        Ray ray;
        ray.dir = randomUnit(rng);
        ray.org = center - ray.dir * (size * (1.f + 4.f * unit(rng))) + randomUnit(rng) * (0.3f * size);
        ray.tfar = std::numeric_limits<float>::infinity();
        const std::vector<LaneAnswer> expected = scalarTestAnswers(tris, ray);
        lanesHit += expected.size();
        for (const StoredTriangle& tri : tris) degenerateLanes += dot(cross(tri.v1 - tri.v0, tri.v2 - tri.v0), cross(tri.v1 - tri.v0, tri.v2 - tri.v0)) == 0.f;
        expectEveryLaneTypeAnswers(block, ray, expected,
                                   "offset " + std::to_string(offset) + " size " + std::to_string(size));
      }
  EXPECT_GT(lanesHit, 2000u);
  EXPECT_GT(degenerateLanes, 300u);
}

// Rays leaving surfaces (a secondary ray's start triangle, and its neighbours): lanes whose plane
// the ray certainly crosses behind its origin are dropped in float (certainlyBeforeNearLanes) before the
// double-precision second half. Origins on the triangle and 1 to 256 ulps off it to either side,
// directions leaving and entering, down to grazing, near and far from the coordinate origin, small
// and large triangles: every dropped lane is one the scalar test rejects, every lane type answers as
// the scalar test does, and the start triangle of a ray offset the way renderers offset it (256
// ulps) is dropped where the triangle is small beside its distance from the coordinate origin, as
// a mesh's triangles are (the bounds grow with the triangle's size, the offset with its position).
TEST(TriangleBlockLeaf, LanesBehindTheOriginAreDroppedOnlyWhenTheScalarTestRejectsThem) {
  std::mt19937 rng(4711);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t dropped = 0, offsetStarts = 0, offsetStartsDropped = 0, compared = 0;
  for (float offset : {0.f, 1.f, 100.f, 1e4f, 1e6f})
    for (float relativeSize : {1e-4f, 1e-2f, 1.f})
      for (int trial = 0; trial < 300; ++trial) {
        const float size = relativeSize * std::max(offset, 1.f);
        const Vec3f center = randomUnit(rng) * offset;
        StoredTriangle tris[4];
        // Lane `start` holds the start triangle; the others share its vertices (a fan around
        // it, as a mesh's neighbours do) or lie near it.
        const int start = trial % 4;
        const Vec3f a = center + randomUnit(rng) * size, b = center + randomUnit(rng) * size,
                    c = center + randomUnit(rng) * size;
        tris[start].v0 = a, tris[start].v1 = b, tris[start].v2 = c;
        for (int lane = 0; lane < 4; ++lane) {
          if (lane == start) continue;
          const Vec3f far = center + randomUnit(rng) * size;
          if (lane % 2) tris[lane].v0 = b, tris[lane].v1 = a, tris[lane].v2 = far;  // across edge ab
          else tris[lane].v0 = c, tris[lane].v1 = b, tris[lane].v2 = far;           // across edge bc
        }
        TriangleBlock4 block;
        block.fill(tris, 0, 4);
        const Vec3f normal = cross(b - a, c - a);
        const float normalLength = std::sqrt(dot(normal, normal));
        if (!(normalLength > 0.f)) continue;
        const Vec3f n = normal * (1.f / normalLength);
        // A point on the triangle: inside, on an edge or at a vertex.
        float w1 = unit(rng), w2 = unit(rng);
        if (w1 + w2 > 1.f) w1 = 1.f - w1, w2 = 1.f - w2;
        if (trial % 5 == 1) w2 = 0.f;
        if (trial % 7 == 2) w1 = w2 = 0.f;
        const Vec3f surfacePoint = a + (b - a) * w1 + (c - a) * w2;
        const int ulpChoices[] = {0, 1, 4, 16, 256, -1, -16, -256};
        const int ulps = ulpChoices[trial % 8];
        Vec3f org;
        for (int axis = 0; axis < 3; ++axis) {
          float p = surfacePoint[axis];
          const int steps = int(std::lround(float(ulps) * std::fabs(n[axis])));
          const bool up = (n[axis] > 0.f) == (ulps > 0);
          for (int k = 0; k < std::abs(steps); ++k) p = up ? std::nextafter(p, std::numeric_limits<float>::infinity()) : nextFloatDown(p);
          (&org.x)[axis] = p;
        }
        // Leaving (along n) or entering, from straight out to grazing.
        const float cosines[] = {1.f, 0.5f, 0.05f, 1e-3f, 1e-6f};
        const float cosine = cosines[(trial / 8) % 5];
        Vec3f side = cross(n, randomUnit(rng));
        const float sideLength = std::sqrt(dot(side, side));
        if (!(sideLength > 0.f)) continue;
        side = side * (1.f / sideLength);
        const float sine = std::sqrt(std::max(0.f, 1.f - cosine * cosine));
        const bool leaving = (trial / 40) % 2 == 0;
        Ray ray;
        ray.org = org;
        ray.dir = n * (leaving ? cosine : -cosine) + side * sine;
        ray.tnear = (trial / 80) % 3 == 0 ? 0.f : (trial / 80) % 3 == 1 ? 1e-7f * size : 0x1p-149f;
        ray.tfar = std::numeric_limits<float>::infinity();
        const WatertightRay wr(ray);
        const std::vector<LaneAnswer> expected = scalarTestAnswers(tris, ray);
        for (int kind = 0; kind < 2; ++kind) {
          const DropOutcome o = dropOutcome(block, wr, kind, expected,
                                            "offset " + std::to_string(offset) + " size " + std::to_string(size) +
                                                " ulps " + std::to_string(ulps) + " cosine " + std::to_string(cosine));
          if (kind != 0) continue;
          dropped += size_t(__builtin_popcount(unsigned(o.dropped())));
          if (ulps == 256 && leaving && cosine >= 0.05f && offset >= 1.f && relativeSize <= 1e-2f && ((o.all >> start) & 1)) {
            ++offsetStarts;
            offsetStartsDropped += o.dropped() >> start & 1;
          }
        }
        expectEveryLaneTypeAnswers(block, ray, expected,
                                   "offset " + std::to_string(offset) + " ulps " + std::to_string(ulps));
        ++compared;
      }
  EXPECT_GT(compared, 4000u);
  EXPECT_GT(dropped, 1000u);
  ASSERT_GT(offsetStarts, 50u);
  EXPECT_GE(double(offsetStartsDropped), 0.9 * double(offsetStarts)) << offsetStartsDropped << " of " << offsetStarts;
}

// Rays whose segment starts ahead of their origin (tnear > 0): lanes whose hit certainly lies before
// tnear are dropped in float (certainlyBeforeNearLanes). tnear placed around the hit distance of a
// lane the ray crosses, from a sixteenth below it to a sixteenth above, down to one ulp either
// side, near and far from the coordinate origin, small and large triangles, flat blocks under
// grazing rays, directions of any length:
// every dropped lane is one the scalar test (with that tnear) rejects, every lane type answers as it
// does, and lanes whose hit lies a sixteenth or more before tnear are dropped nearly always.
TEST(TriangleBlockLeaf, LanesBeforeTnearAreDroppedOnlyWhenTheScalarTestRejectsThem) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t compared = 0, dropped = 0, wellBefore = 0, wellBeforeDropped = 0;
  const float relativeNear[] = {-0x1p-4f, -0x1p-10f, -0x1p-20f, 0.f, 0x1p-20f, 0x1p-10f, 0x1p-4f, 1.f};
  for (float offset : {0.f, 10.f, 1e4f, 1e6f})
    for (float relativeSize : {1e-4f, 1e-2f, 1.f})
      for (int trial = 0; trial < 150; ++trial) {
        const float size = relativeSize * std::max(offset, 1.f);
        const Vec3f center = randomUnit(rng) * offset;
        // Every third block lies flat (z within a thousandth of its size) under a grazing ray.
        const bool grazing = trial % 3 == 0;
        const Vec3f flat{1.f, 1.f, grazing ? 1e-3f : 1.f};
        const auto vertex = [&] {
          const Vec3f d = randomUnit(rng) * size;
          return center + Vec3f{d.x * flat.x, d.y * flat.y, d.z * flat.z};
        };
        StoredTriangle tris[4];
        for (StoredTriangle& tri : tris) tri.v0 = vertex(), tri.v1 = vertex(), tri.v2 = vertex();
        TriangleBlock4 block;
        block.fill(tris, 0, 4);
        Ray ray;
        const float length = 0.01f + 100.f * unit(rng);  // tnear counts in direction lengths
        Vec3f toward = randomUnit(rng);
        if (grazing) {
          const float slope = trial % 2 ? 0.05f : 0.005f;
          toward = Vec3f{toward.x, toward.y, 0.f};
          const float across = std::sqrt(dot(toward, toward));
          if (!(across > 0.f)) continue;
          toward = toward * (1.f / across) + Vec3f{0.f, 0.f, -slope};
        }
        ray.dir = toward * length;
        const Vec3f aside = randomUnit(rng) * (0.3f * size);  // not off the flat block's plane
        ray.org = center - toward * (size * (1.f + 4.f * unit(rng))) + Vec3f{aside.x, aside.y, grazing ? 0.f : aside.z};
        ray.tfar = std::numeric_limits<float>::infinity();
        const std::vector<LaneAnswer> fromOrigin = scalarTestAnswers(tris, ray);
        if (fromOrigin.empty()) continue;
        const float hitT = fromOrigin[size_t(trial) % fromOrigin.size()].hit.t;
        std::vector<float> nears;
        for (float relative : relativeNear) nears.push_back(hitT * (1.f + relative));
        nears.push_back(std::nextafter(hitT, std::numeric_limits<float>::infinity()));
        for (int ulps = 1; ulps <= 64; ulps *= 4) {  // just below the hit
          float below = hitT;
          for (int k = 0; k < ulps; ++k) below = nextFloatDown(below);
          nears.push_back(below);
        }
        for (float tnear : nears) {
          if (!(tnear > 0.f)) continue;
          ray.tnear = tnear;
          const WatertightRay wr(ray);
          const std::vector<LaneAnswer> expected = scalarTestAnswers(tris, ray);
          for (int kind = 0; kind < 2; ++kind) {
            const DropOutcome o = dropOutcome(block, wr, kind, expected,
                                              "offset " + std::to_string(offset) + " size " + std::to_string(size) +
                                                  " tnear " + std::to_string(tnear));
            if (kind != 0) continue;
            dropped += size_t(__builtin_popcount(unsigned(o.dropped())));
            for (const LaneAnswer& answer : fromOrigin) {
              if (!(answer.hit.t * (1.f + 0x1p-4f) <= tnear) || !((o.all >> answer.lane) & 1)) continue;
              ++wellBefore;
              wellBeforeDropped += o.dropped() >> answer.lane & 1;
            }
          }
          expectEveryLaneTypeAnswers(block, ray, expected,
                                     "offset " + std::to_string(offset) + " tnear " + std::to_string(tnear));
          ++compared;
        }
      }
  std::printf("compared %zu, dropped %zu, hits a sixteenth or more before tnear %zu (dropped %zu)\n", compared, dropped,
              wellBefore, wellBeforeDropped);
  EXPECT_GT(compared, 5000u);
  EXPECT_GT(dropped, 1000u);
  ASSERT_GT(wellBefore, 1000u);
  EXPECT_GE(double(wellBeforeDropped), 0.9 * double(wellBefore)) << wellBeforeDropped << " of " << wellBefore;
}

// Shadow rays as a renderer casts them: from a hit point on the triangle (not offset), towards a
// light, with tnear a thousandth of the way there. The start triangle lies before tnear and is
// dropped in float (certainlyBeforeNearLanes) wherever the ray leaves the surface at a fair angle;
// no lane the scalar test hits is dropped.
TEST(TriangleBlockLeaf, ShadowRaysDropTheirStartTriangleBeforeTheSecondHalf) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t starts = 0, startsDropped = 0;
  for (float offset : {0.f, 1.f, 100.f, 1e4f, 1e6f})
    for (float relativeSize : {1e-4f, 1e-2f, 1.f})
      for (int trial = 0; trial < 200; ++trial) {
        const float size = relativeSize * std::max(offset, 1.f);
        const Vec3f center = randomUnit(rng) * offset;
        StoredTriangle tris[4];
        const Vec3f a = center + randomUnit(rng) * size, b = center + randomUnit(rng) * size,
                    c = center + randomUnit(rng) * size;
        tris[0].v0 = a, tris[0].v1 = b, tris[0].v2 = c;
        for (int lane = 1; lane < 4; ++lane)  // neighbours across the start triangle's edges
          tris[lane].v0 = lane == 2 ? c : b, tris[lane].v1 = lane == 2 ? b : a,
          tris[lane].v2 = center + randomUnit(rng) * size;
        TriangleBlock4 block;
        block.fill(tris, 0, 4);
        const Vec3f normal = cross(b - a, c - a);
        const float normalLength = std::sqrt(dot(normal, normal));
        if (!(normalLength > 0.f)) continue;
        const Vec3f n = normal * (1.f / normalLength);
        float w1 = unit(rng), w2 = unit(rng);
        if (w1 + w2 > 1.f) w1 = 1.f - w1, w2 = 1.f - w2;
        Vec3f side = cross(n, randomUnit(rng));
        const float sideLength = std::sqrt(dot(side, side));
        if (!(sideLength > 0.f)) continue;
        side = side * (1.f / sideLength);
        const float cosine = 0.5f + 0.5f * unit(rng);
        const Vec3f toLight = (n * cosine + side * std::sqrt(1.f - cosine * cosine)) * (size * (2.f + 100.f * unit(rng)));
        Ray ray;
        ray.org = a + (b - a) * w1 + (c - a) * w2;
        ray.dir = toLight;
        ray.tnear = 1e-3f;
        ray.tfar = 1.f;
        const std::vector<LaneAnswer> expected = scalarTestAnswers(tris, ray);
        const DropOutcome o = dropOutcome(block, WatertightRay(ray), 1, expected, "shadow ray, offset " + std::to_string(offset));
        if (o.all & 1) {
          ++starts;
          startsDropped += o.dropped() & 1;
        }
        expectEveryLaneTypeAnswers(block, ray, expected, "shadow ray, offset " + std::to_string(offset));
      }
  ASSERT_GT(starts, 500u);
  EXPECT_GE(double(startsDropped), 0.95 * double(starts)) << startsDropped << " of " << starts;
}

}  // namespace
}  // namespace obvh
