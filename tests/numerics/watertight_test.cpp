// Closed meshes must not leak: every ray from inside a closed mesh hits it, including rays aimed
// exactly at shared edges and vertices. Runs on obvh alone, through the public API.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "obvh_scene.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

// Rays from an interior point towards every vertex and edge point of the mesh (plus jittered
// origins); counts the ones that escape.
size_t countLeaks(const MeshData& mesh, const float inside[3], size_t raysPerTarget, uint32_t seed,
                  std::string& firstLeak) {
  ObvhScene s({mesh});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
  const int corners = mesh.quads ? 4 : 3;
  size_t leaks = 0;
  for (size_t prim = 0; prim < mesh.primitiveCount(); ++prim)
    for (int c = 0; c < corners; ++c) {
      const uint32_t a = mesh.indices[prim * corners + c], b = mesh.indices[prim * corners + (c + 1) % corners];
      for (size_t r = 0; r < raysPerTarget; ++r) {
        const float w = r == 0 ? 0.f : float(r) / float(raysPerTarget);  // r == 0: the vertex itself
        float org[3], dir[3];
        for (int axis = 0; axis < 3; ++axis) {
          org[axis] = inside[axis] + (r ? jitter(rng) : 0.f);
          dir[axis] = (1 - w) * mesh.vertices[3 * a + axis] + w * mesh.vertices[3 * b + axis] - org[axis];
        }
        const RTCRayHit rh = s.intersect(makeRay(org, dir));
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || !s.occluded(makeRay(org, dir))) {
          if (leaks++ == 0) {
            char buf[256];
            std::snprintf(buf, sizeof buf, "org=(%a,%a,%a) dir=(%a,%a,%a)", rh.ray.org_x, rh.ray.org_y, rh.ray.org_z,
                          rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
            firstLeak = buf;
          }
        }
      }
    }
  return leaks;
}

TEST(Watertight, IcosphereHasNoLeaksThroughEdgesAndVertices) {
  const float center[3] = {0.1f, -0.2f, 0.3f};
  const MeshData mesh = icosphere(4, 1.f, center);  // 5120 triangles, 15360 edge targets
  std::string first;
  EXPECT_EQ(countLeaks(mesh, center, 8, 1, first), 0u) << "first leak: " << first;
}

TEST(Watertight, QuadBoxHasNoLeaks) {
  const float lo[3] = {-1.f, -2.f, -0.5f}, hi[3] = {3.f, 1.f, 0.7f}, inside[3] = {0.3f, -0.4f, 0.1f};
  std::string first;
  EXPECT_EQ(countLeaks(box(lo, hi, true), inside, 2000, 2, first), 0u) << "first leak: " << first;
  EXPECT_EQ(countLeaks(box(lo, hi, false), inside, 1000, 3, first), 0u) << "first leak: " << first;
}

TEST(Watertight, FarFromOriginIcosphereHasNoLeaks) {
  const float center[3] = {1e4f, -2e4f, 3e4f};
  const MeshData mesh = icosphere(3, 10.f, center);
  std::string first;
  EXPECT_EQ(countLeaks(mesh, center, 8, 4, first), 0u) << "first leak: " << first;
}

}  // namespace
}  // namespace obvh::test
