// The leaf blocks' test against the scalar watertight test, where the block test decides something
// the scalar one does not: the distance cull (lanesWithinSegment) that drops lanes before the
// double-precision second half.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "math/float_steps.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "traversal/triangle_block_leaf.h"

namespace obvh {
namespace {

struct BlockAnswer {
  bool hit = false;
  float t = 0.f;
};

template <typename F4>
BlockAnswer testBlock(const TriangleBlock4& block, const Ray& ray) {
  static const uint32_t allMasks[1] = {0xFFFFFFFFu};
  TriangleSet set;
  set.geometryMasks = allMasks;
  BlockAnswer answer;
  visitBlockHits<F4>(set, block, WatertightRay(ray), ray, [&](int lane, const TriangleHit& th) {
    EXPECT_EQ(lane, 0);
    answer = {true, th.t};
    return true;
  });
  return answer;
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
// one float before it. A lane may be culled only where the scalar test has no hit in the segment:
// with the hit at the nearest vertex, that vertex's rounded distance can exceed t, which is what
// the cull's slack is for (without it, this test fails).
TEST(TriangleBlockLeaf, DistanceCullKeepsEveryHitInTheSegment) {
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
              const BlockAnswer sse = testBlock<simd::Float4Sse>(block, segment);
              const BlockAnswer reference = testBlock<simd::FloatScalar<4>>(block, segment);
              EXPECT_EQ(sse.hit, scalarHit) << "offset " << offset << " size " << size << " distance " << distance;
              EXPECT_EQ(reference.hit, scalarHit);
              if (scalarHit && sse.hit) {
                EXPECT_EQ(sse.t, scalar.t);
              }
            }
          }
  EXPECT_GT(hitsChecked, 500);
}

}  // namespace
}  // namespace obvh
