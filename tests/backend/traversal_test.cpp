// The BVH traversal must return exactly what a brute-force loop over all triangles with the same
// triangle test returns (the scalar reference path), for closest and any hit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "intersect/watertight_triangle.h"
#include "scene/scene_accel.h"
#include "backend_mesh_desc.h"
#include "test_scenes.h"
#include "traversal/box_test.h"

namespace obvh {
namespace {

struct Scene {
  test::MeshData mesh;
  SceneAccel accel;
  QueryState state;

  explicit Scene(test::MeshData m) : mesh(std::move(m)) {
    SceneDesc scene;
    scene.meshes = {tools::backendMeshDesc(mesh)};
    scene.geometryIdLimit = 1;
    accel.build(scene, BuildOptions{});
  }

  Vec3f vertex(uint32_t i) const { return {mesh.vertices[3 * i], mesh.vertices[3 * i + 1], mesh.vertices[3 * i + 2]}; }

  // Brute force over every triangle, in primitive order.
  bool bruteForce(Ray& ray, Hit& hit) const {
    const WatertightRay wr(ray);
    bool found = false;
    for (size_t p = 0; p < mesh.primitiveCount(); ++p) {
      const uint32_t* idx = &mesh.indices[3 * p];
      TriangleHit th;
      if (intersectWatertight(wr, ray, vertex(idx[0]), vertex(idx[1]), vertex(idx[2]), th)) {
        ray.tfar = th.t;
        hit.primID = uint32_t(p);
        found = true;
      }
    }
    return found;
  }
};

TEST(Traversal, ClosestAndAnyHitMatchBruteForce) {
  Scene scene(test::randomTriangleSoup(3000, 3));
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> unit(-0.5f, 1.5f);
  size_t hits = 0;
  for (int i = 0; i < 20000; ++i) {
    Ray ray;
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.dir = Vec3f{unit(rng), unit(rng), unit(rng)} - ray.org;
    ray.tnear = 0.f;
    ray.tfar = std::numeric_limits<float>::infinity();
    Ray a = ray, b = ray;
    Hit ha, hb;
    const bool fa = scene.accel.intersect(a, ha, scene.state);
    const bool fb = scene.bruteForce(b, hb);
    ASSERT_EQ(fa, fb) << i;
    EXPECT_EQ(scene.accel.occluded(ray, scene.state), fb) << i;
    if (fa) {
      ++hits;
      EXPECT_EQ(a.tfar, b.tfar) << i;  // same kernel, same triangle: bit-identical distance
    }
  }
  EXPECT_GT(hits, 1000u);
}

TEST(Traversal, AxisParallelAndZeroComponentRaysMatchBruteForce) {
  Scene scene(test::randomTriangleSoup(500, 9));
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (int i = 0; i < 6000; ++i) {
    Ray ray;
    const int axis = i % 3;
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.org[axis] = (i % 2) ? -1.f : 2.f;
    ray.dir = {0.f, 0.f, 0.f};
    ray.dir[axis] = (i % 2) ? 1.f : -1.f;
    if (i % 5 == 0) ray.dir[(axis + 1) % 3] = -0.f;  // negative zero component
    ray.tfar = std::numeric_limits<float>::infinity();
    Ray a = ray, b = ray;
    Hit ha, hb;
    ASSERT_EQ(scene.accel.intersect(a, ha, scene.state), scene.bruteForce(b, hb)) << i;
    EXPECT_EQ(a.tfar, b.tfar);
  }
}

TEST(BoxTest, ConservativeForRaysGrazingAFace) {
  Box3f box;
  box.extend({0.f, 0.f, 0.f});
  box.extend({1.f, 1.f, 1.f});
  // Rays exactly along the faces and edges of the box must enter it.
  for (float y : {0.f, 1.f})
    for (float z : {0.f, 0.5f, 1.f}) {
      Ray ray;
      ray.org = {-5.f, y, z};
      ray.dir = {1.f, 0.f, 0.f};
      ray.tfar = std::numeric_limits<float>::infinity();
      EXPECT_LT(intersectBox(BoxRay(ray), box, ray.tnear, ray.tfar), std::numeric_limits<float>::infinity());
    }
}

TEST(BoxTest, NanRaysEnterNothing) {
  Box3f box;
  box.extend({0.f, 0.f, 0.f});
  box.extend({1.f, 1.f, 1.f});
  Ray ray;
  ray.org = {std::nanf(""), 0.5f, 0.5f};
  ray.dir = {1.f, 0.f, 0.f};
  ray.tfar = std::numeric_limits<float>::infinity();
  EXPECT_EQ(intersectBox(BoxRay(ray), box, ray.tnear, ray.tfar), std::numeric_limits<float>::infinity());
}

}  // namespace
}  // namespace obvh
