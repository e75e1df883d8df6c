// The oriented layouts' first test of a ray (traversal/bounds_gate.h): it may let a ray through that
// misses the box, never cull one whose segment reaches it, in the hard cases of a slab test (rays
// that do not move along an axis, origins on a bounding plane, segments ending on a face, boxes
// behind the origin), in the SSE kernel and the scalar reference alike; and through the whole
// oriented layout, rays grazing the scene's box answer as the binary oriented tree does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "backend_mesh_desc.h"
#include "scene/scene_accel.h"
#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "stack_generator.h"
#include "traversal/bounds_gate.h"

namespace obvh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Both instantiations give the same verdict; returns it.
bool passes(const GateBox& box, const Ray& ray) {
  const bool sse = mayEnterBox<simd::Float4Sse>(box, ray);
  EXPECT_EQ(sse, mayEnterBox<simd::FloatScalar<4>>(box, ray));
  return sse;
}

const GateBox kUnitBox(Box3f{Vec3f{0.f, 0.f, 0.f}, Vec3f{1.f, 1.f, 1.f}});

TEST(BoundsGate, CullsRaysThatMissAndKeepsRaysThatEnter) {
  EXPECT_TRUE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f})));
  EXPECT_TRUE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 0.5f}, {0.3f, -0.2f, 1.f})));  // origin inside
  EXPECT_TRUE(passes(kUnitBox, rayAlong({-2.f, -2.f, -2.f}, {1.f, 1.f, 1.f})));      // through the corners
  EXPECT_FALSE(passes(kUnitBox, rayAlong({1.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f})));     // beside it, straight down
  EXPECT_FALSE(passes(kUnitBox, rayAlong({-2.f, 0.5f, 0.5f}, {1.f, 1.f, 0.f})));     // passes above one edge
  EXPECT_FALSE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, 1.f})));      // the box behind the origin
  EXPECT_FALSE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f}, 0.f, 1.5f)));  // segment ends short
  EXPECT_FALSE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f}, 4.5f)));       // starts beyond it
  // Negative tnear reaches back to a box behind the origin.
  EXPECT_TRUE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, 1.f}, -2.5f)));
  EXPECT_FALSE(passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, 1.f}, -1.5f)));
}

TEST(BoundsGate, RaysAlongAnAxisAndOriginsOnThePlanes) {
  // Origins on each bounding plane, moving within it (0 * inf in the slab's distances).
  for (const float side : {0.f, 1.f}) {
    EXPECT_TRUE(passes(kUnitBox, rayAlong({side, 0.5f, 3.f}, {0.f, 0.f, -1.f})));
    EXPECT_TRUE(passes(kUnitBox, rayAlong({side, 0.5f, 3.f}, {-0.f, 0.f, -1.f})));
    EXPECT_TRUE(passes(kUnitBox, rayAlong({0.5f, side, 3.f}, {0.f, -0.f, -1.f})));
    EXPECT_TRUE(passes(kUnitBox, rayAlong({side, side, -4.f}, {0.f, 0.f, 1.f})));
  }
  // The float just outside a plane, moving parallel to it.
  EXPECT_FALSE(passes(kUnitBox, rayAlong({std::nextafter(1.f, 2.f), 0.5f, 3.f}, {0.f, 0.f, -1.f})));
  EXPECT_FALSE(passes(kUnitBox, rayAlong({-0x1p-140f, 0.5f, 3.f}, {0.f, 0.f, -1.f})));
  // A ray along a face's plane from outside the box entirely.
  EXPECT_TRUE(passes(kUnitBox, rayAlong({-3.f, 1.f, 0.5f}, {1.f, 0.f, 0.f})));
}

// The smallest float not below x, and the largest not above it.
float floatAtOrAbove(double x) {
  const float f = float(x);
  return double(f) < x ? std::nextafter(f, kInf) : f;
}
float floatAtOrBelow(double x) {
  const float f = float(x);
  return double(f) > x ? std::nextafter(f, -kInf) : f;
}

TEST(BoundsGate, SegmentsEndingOnAFaceAreKept) {
  // Segments that end where the exact ray enters the box (tfar the exact entry rounded up), or
  // start where it leaves (tnear the exact exit rounded down): the computed distances are a few
  // ulps off either way, so only the slab test's widening keeps them. From far away and up close,
  // along slanted directions through the top face and out of the bottom.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (int i = 0; i < 20000; ++i) {
    const float scale = std::ldexp(1.f, int(unit(rng) * 40.f) - 20);
    const Vec3f org{unit(rng) + (unit(rng) - 0.5f) * scale, unit(rng) + (unit(rng) - 0.5f) * scale, 1.f + unit(rng) * scale};
    const Vec3f target{0.25f + 0.5f * unit(rng), 0.25f + 0.5f * unit(rng), 0.5f};
    const Vec3f dir = target - org;
    // Through the top face only when the entry is there: along z the slab is entered last.
    const double entry = (1.0 - double(org.z)) / double(dir.z), exit = (0.0 - double(org.z)) / double(dir.z);
    double entryXY = -1e300, exitXY = 1e300;
    for (int a = 0; a < 2; ++a) {
      const double t0 = (0.0 - double(org[a])) / double(dir[a]), t1 = (1.0 - double(org[a])) / double(dir[a]);
      entryXY = std::max(entryXY, std::min(t0, t1));
      exitXY = std::min(exitXY, std::max(t0, t1));
    }
    if (!(entryXY <= entry && exit <= exitXY && entry > 0.0)) continue;
    EXPECT_TRUE(passes(kUnitBox, rayAlong(org, dir, 0.f, floatAtOrAbove(entry)))) << i;
    EXPECT_TRUE(passes(kUnitBox, rayAlong(org, dir, floatAtOrBelow(exit), kInf))) << i;
  }
}

TEST(BoundsGate, NanAndInfiniteRaysDoNotCrashAndUnboundedBoxesPassEverything) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  passes(kUnitBox, rayAlong({nan, 0.5f, 3.f}, {0.f, 0.f, -1.f}));
  passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {nan, nan, nan}));
  passes(kUnitBox, rayAlong({0.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f}, nan, nan));
  EXPECT_FALSE(passes(kUnitBox, rayAlong({kInf, 0.5f, 3.f}, {0.f, 0.f, -1.f})));
  const GateBox unbounded;
  EXPECT_TRUE(passes(unbounded, rayAlong({1e30f, -1e30f, 3.f}, {0.f, 0.f, -1.f})));
  EXPECT_TRUE(passes(unbounded, rayAlong({0.f, 0.f, 0.f}, {0.f, 0.f, 0.f})));
}

// Rays aimed at the box's faces and edges, a few ulps either side, slanted from afar and straight
// down: the gated layout answers each as the reference does.
void expectGrazingRaysAnswerAlike(const SceneAccel& wide, const SceneAccel& binary, const Box3f& bounds) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const QueryState state;
  size_t hits = 0;
  for (int i = 0; i < 40000; ++i) {
    // A point on the box's surface (a face, or an edge for every fourth ray), nudged by a few ulps.
    Vec3f target{bounds.lower.x + unit(rng) * (bounds.upper.x - bounds.lower.x),
                 bounds.lower.y + unit(rng) * (bounds.upper.y - bounds.lower.y),
                 bounds.lower.z + unit(rng) * (bounds.upper.z - bounds.lower.z)};
    const int axis = i % 3;
    target[axis] = (i / 3) % 2 ? bounds.upper[axis] : bounds.lower[axis];
    if (i % 4 == 0) target[(axis + 1) % 3] = bounds.upper[(axis + 1) % 3];
    for (int a = 0; a < 3; ++a) target[a] = std::nextafter(target[a], unit(rng) < 0.5f ? -kInf : kInf);
    const bool down = i % 5 == 0;  // as an orthographic view's rays
    const Vec3f dir = down ? Vec3f{0.f, 0.f, -1.f} : Vec3f{unit(rng) - 0.5f, unit(rng) - 0.5f, -unit(rng)};
    const Vec3f org = down ? Vec3f{target.x, target.y, bounds.upper.z + 1.f} : target - dir * 50.f;
    Ray a = rayAlong(org, dir), b = a;
    Hit ha, hb;
    const bool fa = wide.intersect(a, ha, state), fb = binary.intersect(b, hb, state);
    ASSERT_EQ(fa, fb) << "ray " << i;
    ASSERT_EQ(wide.occluded(rayAlong(org, dir), state), binary.occluded(rayAlong(org, dir), state)) << "ray " << i;
    hits += fa;
    // The distance only: which of two triangles meeting at the hit is reported depends on the
    // order of the visits, which differs between the trees.
    if (fa) {
      ASSERT_EQ(a.tfar, b.tfar) << "ray " << i;
    }
  }
  EXPECT_GT(hits, 1000u);
}

// Through the whole layout: rays aimed at the scene box's faces, edges and just past them, from
// afar and along the axes, find what the binary oriented tree (no gate) finds.
TEST(BoundsGate, GrazingRaysAnswerAsTheBinaryOrientedTree) {
  const tools::SceneData scene = tools::generateStack(tools::findStackPreset("small-1.5k")->params, "small-1.5k").asScene();
  const SceneDesc desc = tools::backendSceneDesc(scene);
  const Box3f bounds = tools::backendSceneBounds(scene);
  BuildOptions reference;
  reference.layout = AccelLayout::Obb;
  reference.maxLeafSize = 0;
  reference.obbWidth = 2;
  SceneAccel binary;
  binary.build(desc, reference);
  for (const int width : {4, 8}) {
    if (width == 8 && !simd::cpuHasAvx2()) continue;  // eight-wide oriented nodes need AVX2
    BuildOptions gated = reference;
    gated.obbWidth = width;
    gated.obbPalette = width == 8 ? 7 : 0;  // the devices' defaults
    SceneAccel wide;
    wide.build(desc, gated);
    expectGrazingRaysAnswerAlike(wide, binary, bounds);
  }
}

}  // namespace
}  // namespace obvh
