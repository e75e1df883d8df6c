// The numerics suite's hard cases that are not about leaks, through Embree (default and
// RTC_SCENE_FLAG_ROBUST) and obvh on the same rays: degenerate triangles, special ray component
// values, segment boundaries, NaN and infinity in vertices. A differing answer must be
// proven ambiguous in double precision.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "crossval_harness.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

RTCRay ray(float ox, float oy, float oz, float dx, float dy, float dz, float tnear = 0.f, float tfar = kInfinity) {
  RTCRay r{};
  r.org_x = ox, r.org_y = oy, r.org_z = oz;
  r.dir_x = dx, r.dir_y = dy, r.dir_z = dz;
  r.tnear = tnear, r.tfar = tfar;
  r.mask = 0xFFFFFFFFu;
  return r;
}

class SpecialCases : public ::testing::TestWithParam<RTCSceneFlags> {
 protected:
  void expectSameAnswers(const char* what, const SceneData& scene, const std::vector<RTCRay>& rays) {
    expectNoMismatch(what, crossvalIntersect1(scene, rays, GetParam()));
    expectNoMismatch(what, crossvalOccluded1(scene, rays, GetParam()));
  }
};

TEST_P(SpecialCases, DegenerateTriangles) {
  MeshData mesh;
  mesh.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0,                    // a good triangle, z = 0
                   0, 0, 1, 0, 0, 1, 1, 1, 1,                    // repeated vertex, z = 1
                   0, 0, 2, 0.5f, 0.5f, 2, 1, 1, 2,              // collinear, z = 2
                   0.3f, 0.3f, 3, 0.3f, 0.3f, 3, 0.3f, 0.3f, 3};  // a point, z = 3
  mesh.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(-0.2f, 1.2f);
  std::vector<RTCRay> rays;
  for (int i = 0; i < 20000; ++i) rays.push_back(ray(unit(rng), unit(rng), 5.f, 0.1f * unit(rng), 0.1f * unit(rng), -1.f));
  for (float x : {0.f, 0.3f, 0.5f, 1.f}) rays.push_back(ray(x, x, 5.f, 0.f, 0.f, -1.f));  // through the degenerate points
  rays.push_back(ray(-1.f, -1.f, 2.f, 1.f, 1.f, 0.f));  // along the collinear triangle
  expectSameAnswers("degenerate triangles", single("degenerate", mesh), rays);
}

TEST_P(SpecialCases, SpecialDirectionComponentsAndAxisParallelRays) {
  const float lo[3] = {-1.f, -1.f, -1.f}, hi[3] = {1.f, 1.f, 1.f};
  const float denormal = std::numeric_limits<float>::denorm_min();
  std::vector<RTCRay> rays;
  for (float a : {0.f, -0.f, denormal, -denormal, 1e-30f})
    for (float b : {0.f, -0.f, denormal, -denormal, 1e-30f})
      for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.f, -1.f}) {
          float d[3];
          d[axis] = sign, d[(axis + 1) % 3] = a, d[(axis + 2) % 3] = b;
          rays.push_back(ray(0.25f, -0.5f, 0.1f, d[0], d[1], d[2]));  // from inside
          rays.push_back(ray(-3.f * d[0] + 0.3f * d[1], -3.f * d[1] + 0.3f * d[2], -3.f * d[2] + 0.3f * d[0], d[0], d[1], d[2]));
        }
  rays.push_back(ray(-5.f, 1.f, 0.2f, 1.f, 0.f, 0.f));  // in the plane of a face
  rays.push_back(ray(-5.f, 1.f, 1.f, 1.f, 0.f, 0.f));   // along an edge
  expectSameAnswers("special directions", single("box", box(lo, hi, false)), rays);
}

TEST_P(SpecialCases, SegmentBoundariesAndOriginsOnTheSurface) {
  MeshData tri;
  tri.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  tri.indices = {0, 1, 2};
  const std::vector<RTCRay> rays = {ray(0.2f, 0.2f, 1.f, 0, 0, -1, 0.f, 1.f), ray(0.2f, 0.2f, 1.f, 0, 0, -1, 1.f, kInfinity),
                                    ray(0.2f, 0.2f, 1.f, 0, 0, -1, 1.f, 1.f),  ray(0.2f, 0.2f, 1.f, 0, 0, -1, 2.f, 0.5f),
                                    ray(0.2f, 0.2f, 0.f, 0, 0, -1),           ray(0.2f, 0.2f, 0.f, 0, 0, 1),
                                    ray(0.2f, 0.2f, 1.f, 0, 0, -1, 0.f, kInfinity)};
  expectSameAnswers("segment boundaries", single("triangle", tri), rays);
}

// Only the vertices: Debian's Embree aborts on a ray with NaN or infinite components (an assertion,
// `ray.valid()`, in its traversal), so such rays are tested on obvh alone (numerics suite).
TEST_P(SpecialCases, NanAndInfinityInVertices) {
  SceneData scene;
  scene.name = "poisoned";
  scene.meshes.push_back(randomTriangleSoup(1000, 3));
  MeshData bad = scene.meshes[0];
  for (size_t i = 0; i < bad.vertices.size(); i += 7) bad.vertices[i] = (i / 7) % 2 ? kNaN : kInfinity;
  scene.meshes.push_back(bad);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::vector<RTCRay> rays;
  for (int i = 0; i < 20000; ++i) rays.push_back(ray(unit(rng), unit(rng), 2.f, 0.f, 0.f, -1.f));
  expectSameAnswers("NaN and infinity in vertices", scene, rays);
}

INSTANTIATE_TEST_SUITE_P(Flags, SpecialCases, ::testing::Values(RTC_SCENE_FLAG_NONE, RTC_SCENE_FLAG_ROBUST),
                         [](const ::testing::TestParamInfo<RTCSceneFlags>& info) {
                           return info.param == RTC_SCENE_FLAG_ROBUST ? std::string("robust") : std::string("default");
                         });

}  // namespace
}  // namespace obvh::test
