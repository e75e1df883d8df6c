// The oriented layouts' predicted walk (wide_walk.h, kPredictLanes) and the coherence check that
// chooses it per ray (ray_coherence.h): which rays count as following their predecessor, and that
// the walk with predicted lanes answers every ray exactly as the plain walk does.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

#include "backend_mesh_desc.h"
#include "scene/scene_accel.h"
#include "simd/cpu_features.h"
#include "stack_generator.h"
#include "traversal/ray_coherence.h"

namespace obvh {
namespace {

constexpr float kExtent = 10.f;

// A ray no camera ray follows, so that the next check starts afresh.
void forgetPreviousRay() { followsPreviousRay(rayAlong({1e6f, 1e6f, 1e6f}, {-1.f, 0.f, 0.f}), kExtent); }

TEST(RayCoherence, NeighbouringCameraRaysFollowEachOther) {
  forgetPreviousRay();
  // A 64 x 48 pinhole camera over a scene of extent 10, row by row: every ray but each row's first
  // follows its left neighbour; the first follows the end of the previous row only if the field
  // of view were tiny.
  size_t following = 0, rays = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x, ++rays) {
      const Vec3f dir{(float(x) - 32.f) / 64.f, (float(y) - 24.f) / 64.f, 1.f};
      const bool follows = followsPreviousRay(rayAlong({5.f, 5.f, -20.f}, dir), kExtent);
      following += follows;
      if (x > 0) {
        EXPECT_TRUE(follows) << x << ", " << y;
      }
    }
  EXPECT_GE(following, rays - 48);
  // Orthographic rays: one direction, origins a pixel apart.
  forgetPreviousRay();
  following = 0;
  for (int x = 0; x < 64; ++x) following += followsPreviousRay(rayAlong({float(x) * 0.1f, 3.f, -1.f}, {0.f, 0.f, 1.f}), kExtent);
  EXPECT_EQ(following, 63u);
  // The same ray again (as a renderer's second query of a pixel may be) follows itself.
  EXPECT_TRUE(followsPreviousRay(rayAlong({6.3f, 3.f, -1.f}, {0.f, 0.f, 1.f}), kExtent));
}

TEST(RayCoherence, IncoherentRaysDoNotFollow) {
  std::mt19937 rng(5);
  std::normal_distribution<float> normal;
  std::uniform_real_distribution<float> inScene(0.f, kExtent);
  forgetPreviousRay();
  // From one point in random directions (a point light's rays, diffuse bounces).
  size_t following = 0;
  for (int i = 0; i < 4000; ++i)
    following += followsPreviousRay(rayAlong({5.f, 5.f, 5.f}, {normal(rng), normal(rng), normal(rng)}), kExtent);
  EXPECT_LE(following, 8u);  // two random directions lie within 2.6 degrees once in ~2000 pairs
  // One direction, origins anywhere in the scene (sun shadow rays from scattered points).
  following = 0;
  for (int i = 0; i < 4000; ++i)
    following += followsPreviousRay(rayAlong({inScene(rng), inScene(rng), inScene(rng)}, {0.3f, 1.f, 0.2f}), kExtent);
  EXPECT_LE(following, 8u);
  // Opposite directions from one origin, and directions 5 degrees apart.
  forgetPreviousRay();
  EXPECT_FALSE(followsPreviousRay(rayAlong({1.f, 1.f, 1.f}, {0.f, 0.f, 1.f}), kExtent));
  EXPECT_FALSE(followsPreviousRay(rayAlong({1.f, 1.f, 1.f}, {0.f, 0.f, -1.f}), kExtent));
  EXPECT_FALSE(followsPreviousRay(rayAlong({1.f, 1.f, 1.f}, {std::sin(0.087f), 0.f, -std::cos(0.087f)}), kExtent));
  // NaN rays follow nothing, nor does the ray after them.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(followsPreviousRay(rayAlong({nan, 1.f, 1.f}, {0.f, 0.f, 1.f}), kExtent));
  EXPECT_FALSE(followsPreviousRay(rayAlong({1.f, 1.f, 1.f}, {0.f, 0.f, 1.f}), kExtent));
}

TEST(RayCoherence, EmptySegmentsAreNeitherPredictedNorRecorded) {
  forgetPreviousRay();
  Ray first = rayAlong({1.f, 2.f, 3.f}, {0.f, 1.f, 0.f});
  EXPECT_FALSE(worthPredicting(first, kExtent));
  Ray empty = first;
  empty.org = {9.f, 9.f, 9.f};
  empty.dir = {0.f, -1.f, 0.f};
  empty.tnear = 2.f;
  empty.tfar = 1.f;
  EXPECT_FALSE(worthPredicting(empty, kExtent));
  // The ray after the empty one is judged against the one before it.
  EXPECT_TRUE(worthPredicting(first, kExtent));
}

struct StackScene {
  SceneAccel accel;
  float extent = 0.f;
};

std::unique_ptr<StackScene> buildStack(const char* preset, AccelLayout layout, int obbWidth, int palette) {
  const tools::SceneData scene = tools::generateStack(tools::findStackPreset(preset)->params, preset).asScene();
  const SceneDesc desc = tools::backendSceneDesc(scene);
  BuildOptions options;
  options.layout = layout;
  options.maxLeafSize = 0;
  options.obbWidth = obbWidth;
  options.obbPalette = palette;
  auto out = std::make_unique<StackScene>();
  out->accel.build(desc, options);
  out->extent = tools::backendSceneBounds(scene).largestSide();
  return out;
}

// Rays of a 96 x 72 view, row by row: down the stack (orthographic) and in perspective from
// above one corner, so that consecutive rays follow each other and take the predicted walk.
std::vector<Ray> cameraRays(float extent) {
  std::vector<Ray> rays;
  for (int y = 0; y < 72; ++y)
    for (int x = 0; x < 96; ++x) {
      const float u = (float(x) + 0.5f) / 96.f, v = (float(y) + 0.5f) / 72.f;
      rays.push_back(rayAlong({u * extent, v * extent, 2.f * extent}, {0.f, 0.f, -1.f}));
    }
  for (int y = 0; y < 72; ++y)
    for (int x = 0; x < 96; ++x) {
      const float u = (float(x) + 0.5f) / 96.f, v = (float(y) + 0.5f) / 72.f;
      const Vec3f target{u * extent, v * extent, 0.f};
      const Vec3f eye{-0.3f * extent, -0.4f * extent, 1.5f * extent};
      rays.push_back(rayAlong(eye, target - eye));
    }
  return rays;
}

struct Answer {
  bool hit = false, occluded = false;
  float t = 0.f, u = 0.f, v = 0.f;
  Vec3f Ng{0.f, 0.f, 0.f};
  uint32_t primID = 0;
};

enum class Walk { kPredicted, kPlain };

// Before each query the thread's record is set so that the query's own check picks the walk: the
// ray itself (which it follows) or a ray it does not follow.
Answer trace(const StackScene& scene, const Ray& ray, Walk walk) {
  const auto prepare = [&] {
    if (walk == Walk::kPredicted) followsPreviousRay(ray, scene.extent);
    else forgetPreviousRay();
  };
  const QueryState state;
  Answer a;
  Ray r = ray;
  Hit hit;
  prepare();
  a.hit = scene.accel.intersect(r, hit, state);
  a.t = r.tfar, a.u = hit.u, a.v = hit.v, a.Ng = hit.Ng, a.primID = hit.primID;
  prepare();
  a.occluded = scene.accel.occluded(ray, state);
  return a;
}

// Every ray of the views through both walks: bit-identical answers.
void expectPredictedWalkAnswersAsThePlainWalk(const char* preset, AccelLayout layout, int obbWidth, int palette) {
  const auto scene = buildStack(preset, layout, obbWidth, palette);
  const std::vector<Ray> rays = cameraRays(scene->extent);
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Answer plain = trace(*scene, rays[i], Walk::kPlain);
    const Answer predicted = trace(*scene, rays[i], Walk::kPredicted);
    ASSERT_EQ(predicted.hit, plain.hit) << preset << " ray " << i;
    EXPECT_EQ(predicted.occluded, plain.occluded) << preset << " ray " << i;
    hits += plain.hit;
    if (!plain.hit) continue;
    EXPECT_EQ(predicted.t, plain.t) << preset << " ray " << i;
    EXPECT_EQ(predicted.primID, plain.primID) << preset << " ray " << i;
    EXPECT_EQ(predicted.u, plain.u);
    EXPECT_EQ(predicted.v, plain.v);
    EXPECT_EQ(predicted.Ng.x, plain.Ng.x);
    EXPECT_EQ(predicted.Ng.y, plain.Ng.y);
    EXPECT_EQ(predicted.Ng.z, plain.Ng.z);
  }
  EXPECT_GT(hits, rays.size() / 4) << preset;
}

TEST(PredictedWalk, AnswersAsThePlainWalkOnOrientedLayouts) {
  for (const char* preset : {"small-1.5k", "stepped-6.6k", "mixed-6.9k"}) {
    expectPredictedWalkAnswersAsThePlainWalk(preset, AccelLayout::Obb, 4, 0);
    if (!simd::cpuHasAvx2()) continue;  // eight-wide oriented nodes need AVX2
    expectPredictedWalkAnswersAsThePlainWalk(preset, AccelLayout::Obb, 8, 0);
    expectPredictedWalkAnswersAsThePlainWalk(preset, AccelLayout::Obb, 8, 7);
    expectPredictedWalkAnswersAsThePlainWalk(preset, AccelLayout::Hybrid, 8, 7);
  }
}

}  // namespace
}  // namespace obvh
