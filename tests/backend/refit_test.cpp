// RTC_BUILD_QUALITY_REFIT in the backend: after the vertices move, a refitted tree answers like a
// tree built from scratch; refit refuses what it cannot keep.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

#include "scene/scene_accel.h"
#include "backend_mesh_desc.h"
#include "test_scenes.h"

namespace obvh {
namespace {

struct Animated {
  test::MeshData soup = test::randomTriangleSoup(20000, 41);
  test::MeshData grid = test::quadGrid(40, 0.3f, 42);
  test::MeshData cells = test::gridPatches(30, 0.3f, 43);  // a grid mesh
  SceneDesc desc;

  Animated() {
    for (const test::MeshData* mesh : {&soup, &grid, &cells})
      desc.meshes.push_back(tools::backendMeshDesc(*mesh, uint32_t(desc.meshes.size())));
    desc.geometryIdLimit = 3;
  }
  // A non-rigid motion: every vertex moves differently, so boxes change shape and overlap.
  void animate(float time) {
    for (test::MeshData* mesh : {&soup, &grid, &cells})
      for (size_t i = 0; i + 2 < mesh->vertices.size(); i += 3) {
        float* v = &mesh->vertices[i];
        v[2] += 0.2f * std::sin(6.f * v[0] + time) * std::cos(5.f * v[1]);
        v[0] += 0.05f * std::sin(3.f * v[2] + time);
      }
  }
};

std::vector<Ray> rays(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-0.5f, 1.5f);
  std::vector<Ray> out(20000);
  for (Ray& ray : out) {
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.dir = Vec3f{unit(rng), unit(rng), unit(rng)} - ray.org;
    ray.tfar = std::numeric_limits<float>::infinity();
  }
  return out;
}

TEST(Refit, RefittedTreeAnswersLikeAFreshBuildInEveryAabbLayout) {
  for (AccelLayout layout : {AccelLayout::Bvh2, AccelLayout::Bvh4, AccelLayout::Bvh8}) {
    Animated scene;
    BuildOptions options;
    options.layout = layout;
    options.keepBinaryTree = true;  // as the API asks when every mesh is RTC_BUILD_QUALITY_REFIT
    SceneAccel refitted;
    refitted.build(scene.desc, options);
    const size_t nodesBefore = refitted.triangleLayoutMetrics().nodeCount;
    for (int frame = 1; frame <= 3; ++frame) {
      scene.animate(float(frame));
      ASSERT_TRUE(refitted.refit(scene.desc, options)) << "layout " << int(layout);
      EXPECT_EQ(refitted.triangleLayoutMetrics().nodeCount, nodesBefore);  // the binary topology is kept
      SceneAccel rebuilt;
      rebuilt.build(scene.desc, options);
      const QueryState state;
      size_t hits = 0;
      for (const Ray& ray : rays(uint32_t(frame))) {
        Ray a = ray, b = ray;
        Hit ha, hb;
        const bool fa = refitted.intersect(a, ha, state);
        ASSERT_EQ(fa, rebuilt.intersect(b, hb, state)) << "layout " << int(layout) << " frame " << frame;
        EXPECT_EQ(refitted.occluded(ray, state), rebuilt.occluded(ray, state));
        if (!fa) continue;
        ++hits;
        // The closest distance is unique; only equally distant primitives may be reported differently.
        ASSERT_EQ(a.tfar, b.tfar);
      }
      EXPECT_GT(hits, 5000u);
      EXPECT_EQ(refitted.bounds().upper.z, rebuilt.bounds().upper.z);
    }
  }
}

TEST(Refit, RefusesWhatItCannotKeep) {
  Animated scene;
  BuildOptions options;
  options.keepBinaryTree = true;
  SceneAccel accel;
  EXPECT_FALSE(accel.refit(scene.desc, options));  // nothing built yet
  accel.build(scene.desc, options);
  BuildOptions other = options;
  other.maxLeafSize = 2;
  EXPECT_FALSE(accel.refit(scene.desc, other));  // other build options
  SceneDesc fewer = scene.desc;
  fewer.meshes[0].primCount -= 1;
  EXPECT_FALSE(accel.refit(fewer, options));  // other primitives
  scene.soup.vertices[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(accel.refit(scene.desc, options));  // a primitive became invalid
  BuildOptions oriented = options;
  oriented.layout = AccelLayout::Obb;
  SceneAccel obb;
  obb.build(scene.desc, oriented);
  EXPECT_FALSE(obb.refit(scene.desc, oriented));  // oriented frames are not refitted
}

// Records the primitives a point query visits (a fixed radius).
class SphereQuery : public PointQueryCallbacks {
 public:
  explicit SphereQuery(float radius) : radius_(radius) {}
  float radius() const override { return radius_; }
  float time() const override { return 0.f; }
  bool visit(const void*, uint32_t geomID, uint32_t primID, const PointQueryInstance*) override {
    seen.insert((uint64_t(geomID) << 32) | primID);
    return false;
  }
  std::set<uint64_t> seen;

 private:
  float radius_;
};

// A wide tree built without keepBinaryTree holds only its wide nodes and blocks: it answers as the
// one that keeps its binary tree, holds less, and is rebuilt rather than refitted.
TEST(Refit, WideTreesReleaseTheBinaryTreeUnlessKept) {
  for (AccelLayout layout : {AccelLayout::Bvh4, AccelLayout::Bvh8}) {
    Animated scene;
    BuildOptions options;
    options.layout = layout;
    SceneAccel released;
    released.build(scene.desc, options);
    options.keepBinaryTree = true;
    SceneAccel kept;
    kept.build(scene.desc, options);
    const SceneStats a = released.stats(), b = kept.stats();
    EXPECT_EQ(a.primitiveCount, b.primitiveCount);
    EXPECT_EQ(a.leafCount, b.leafCount);
    EXPECT_EQ(a.nodeCount, b.nodeCount);
    // The binary nodes and the triangle copy (48 bytes a triangle) are gone.
    EXPECT_LE(a.memoryBytes + 48 * a.primitiveCount, b.memoryBytes) << "layout " << int(layout);
    EXPECT_THROW(released.triangleLayoutMetrics(), std::logic_error);
    const QueryState state;
    for (const Ray& ray : rays(7)) {
      Ray r1 = ray, r2 = ray;
      Hit h1, h2;
      ASSERT_EQ(released.intersect(r1, h1, state), kept.intersect(r2, h2, state));
      ASSERT_EQ(r1.tfar, r2.tfar);
      ASSERT_EQ(h1.primID, h2.primID);
    }
    EXPECT_EQ(released.linearBounds().first.upper.z, kept.linearBounds().first.upper.z);
    // Point queries walk the wide tree instead: the same primitives.
    for (const Vec3f& p : {Vec3f{0.5f, 0.5f, 0.5f}, Vec3f{0.1f, 0.9f, 0.3f}, Vec3f{2.f, 2.f, 2.f}}) {
      SphereQuery fromReleased(0.2f), fromKept(0.2f);
      released.pointQuery(p, fromReleased);
      kept.pointQuery(p, fromKept);
      EXPECT_EQ(fromReleased.seen, fromKept.seen) << "layout " << int(layout);
      if (p.x < 1.f) {
        EXPECT_FALSE(fromReleased.seen.empty());
      }
    }
    scene.animate(1.f);
    options.keepBinaryTree = false;
    EXPECT_FALSE(released.refit(scene.desc, options)) << "layout " << int(layout);
  }
}

}  // namespace
}  // namespace obvh
