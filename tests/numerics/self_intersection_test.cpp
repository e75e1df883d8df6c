// Rays spawned from hit points with tools::offsetRayOrigin never hit their own triangle again, near
// the origin and far from it (re-tracing a planar triangle from its own surface is the classic
// self-intersection bug).
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "offset_ray.h"
#include "obvh_scene.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

// Traces primary rays, then from every hit a ray into the hemisphere on the incoming side (a
// reflection-like bounce) and one grazing along the surface; counts re-hits of the same triangle.
size_t selfHits(const MeshData& mesh, const float center[3], float extent, uint32_t seed, size_t& bounces) {
  ObvhScene t({mesh});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  size_t self = 0;
  bounces = 0;
  for (int i = 0; i < 20000; ++i) {
    float org[3], dir[3];
    for (int k = 0; k < 3; ++k) {
      org[k] = center[k] + 2.f * extent * unit(rng);
      dir[k] = center[k] + 0.5f * extent * unit(rng) - org[k];
    }
    const RTCRayHit first = t.intersect(makeRay(org, dir));
    if (first.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    float p[3] = {org[0] + first.ray.tfar * dir[0], org[1] + first.ray.tfar * dir[1], org[2] + first.ray.tfar * dir[2]};
    float n[3] = {first.hit.Ng_x, first.hit.Ng_y, first.hit.Ng_z};
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const float side = (n[0] * dir[0] + n[1] * dir[1] + n[2] * dir[2]) > 0.f ? -1.f : 1.f;  // towards the ray's origin
    for (float& c : n) c *= side / len;
    float start[3];
    tools::offsetRayOrigin(p, n, start);
    for (int variant = 0; variant < 2; ++variant) {
      float out[3];
      for (int k = 0; k < 3; ++k) out[k] = unit(rng);
      float along = out[0] * n[0] + out[1] * n[1] + out[2] * n[2];
      const float lift = variant == 0 ? 1.f : 1e-3f;  // 1: a bounce; 1e-3: nearly grazing
      for (int k = 0; k < 3; ++k) out[k] = out[k] - along * n[k] + lift * n[k];
      const RTCRayHit second = t.intersect(makeRay(start, out));
      ++bounces;
      if (second.hit.geomID != RTC_INVALID_GEOMETRY_ID && second.hit.primID == first.hit.primID) {
        if (self++ == 0)
          std::printf("self hit: prim %u from (%a, %a, %a) dir (%a, %a, %a) t=%a\n", first.hit.primID, start[0],
                      start[1], start[2], out[0], out[1], out[2], second.ray.tfar);
      }
    }
  }
  return self;
}

TEST(SelfIntersection, OffsetOriginsNeverRehitTheirTriangle) {
  for (float offset : {0.f, 1e3f, 1e5f}) {
    const float center[3] = {offset, -0.5f * offset, 0.25f * offset};
    MeshData sphere = icosphere(4, 1.f, center);
    MeshData soup = randomTriangleSoup(3000, 5);
    const float shift[3] = {center[0] - 0.5f, center[1] - 0.5f, center[2] - 0.5f};
    transformMesh(soup, 1.f, shift);
    for (const MeshData* mesh : {&sphere, &soup}) {
      size_t bounces = 0;
      EXPECT_EQ(selfHits(*mesh, center, 1.f, 7, bounces), 0u) << "offset " << offset;
      EXPECT_GT(bounces, 5000u);
    }
  }
}

TEST(SelfIntersection, WithoutTheOffsetRaysDoRehitTheirTriangle) {
  // The helper is what prevents the re-hits: starting exactly at the hit point, grazing rays do
  // come back to their own triangle (or this test setup could not detect the bug).
  const float center[3] = {1e3f, 0.f, 0.f};
  const MeshData sphere = icosphere(4, 1.f, center);
  ObvhScene t({sphere});
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  size_t self = 0;
  for (int i = 0; i < 20000 && self == 0; ++i) {
    float org[3], dir[3];
    for (int k = 0; k < 3; ++k) {
      org[k] = center[k] + 2.f * unit(rng);
      dir[k] = center[k] + 0.5f * unit(rng) - org[k];
    }
    const RTCRayHit first = t.intersect(makeRay(org, dir));
    if (first.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    const float p[3] = {org[0] + first.ray.tfar * dir[0], org[1] + first.ray.tfar * dir[1],
                        org[2] + first.ray.tfar * dir[2]};
    const float out[3] = {-dir[0], -dir[1], -dir[2]};
    const RTCRayHit second = t.intersect(makeRay(p, out));
    self += second.hit.geomID != RTC_INVALID_GEOMETRY_ID && second.hit.primID == first.hit.primID;
  }
  EXPECT_GT(self, 0u);
}

}  // namespace
}  // namespace obvh::test
