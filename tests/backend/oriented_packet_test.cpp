// Packets through the eight-wide oriented layouts (oriented_wide_packets.h): every active lane
// answers as the same ray alone does (closest hit: t, u, v, Ng, primID bit for bit; occlusion,
// which packets trace ray by ray), on stack presets with and without a frame palette, for camera
// packets (one direction: the cached transform; or a pinhole's spread), packets with holes in
// their active mask, empty segments, shortened segments, a NaN among coherent rays, rays on a
// bounding plane whose inverse direction overflows, and incoherent packets (which go ray by ray).
// Inactive lanes are left untouched.
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
#include "traversal/wide_traversal.h"

namespace obvh {
namespace {

struct StackScene {
  SceneAccel accel;
  Box3f bounds;
};

std::unique_ptr<StackScene> buildStack(const char* preset, AccelLayout layout, int palette) {
  const tools::SceneData scene = tools::generateStack(tools::findStackPreset(preset)->params, preset).asScene();
  BuildOptions options;
  options.layout = layout;
  options.maxLeafSize = 0;
  options.obbWidth = 8;
  options.obbPalette = palette;
  options.obbPackets = true;
  auto out = std::make_unique<StackScene>();
  out->accel.build(tools::backendSceneDesc(scene), options);
  out->bounds = tools::backendSceneBounds(scene);
  return out;
}

// Packets of 16 rays: 4 x 4 pixel tiles of an orthographic view down the stack and of a pinhole
// view from above a corner, then rays between random points of the stack's box.
std::vector<Ray> packetRays(const Box3f& box) {
  const Vec3f size = box.upper - box.lower;
  std::vector<Ray> rays;
  const int width = 48, height = 32;
  for (int view = 0; view < 2; ++view)
    for (int ty = 0; ty < height; ty += 4)
      for (int tx = 0; tx < width; tx += 4)
        for (int k = 0; k < 16; ++k) {
          const float u = (float(tx + k % 4) + 0.5f) / width, v = (float(ty + k / 4) + 0.5f) / height;
          const Vec3f target{box.lower.x + u * size.x, box.lower.y + v * size.y, box.lower.z};
          if (view == 0) {
            rays.push_back(rayAlong({target.x, target.y, box.upper.z + size.z}, {0.f, 0.f, -1.f}));
          } else {
            const Vec3f eye{box.lower.x - 0.3f * size.x, box.lower.y - 0.4f * size.y, box.upper.z + size.x};
            rays.push_back(rayAlong(eye, target - eye));
          }
        }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const auto inBox = [&] {
    return Vec3f{box.lower.x + unit(rng) * size.x, box.lower.y + unit(rng) * size.y, box.lower.z + unit(rng) * size.z};
  };
  for (int i = 0; i < 16 * 24; ++i) {
    const Vec3f from = inBox(), to = inBox();
    rays.push_back(rayAlong(from, to - from));
  }
  return rays;
}

struct Answer {
  bool hit = false;
  float t = 0.f, u = 0.f, v = 0.f;
  Vec3f Ng{0.f, 0.f, 0.f};
  uint32_t primID = 0;
};

Answer answerOf(bool hit, const Ray& ray, const Hit& h) {
  Answer a;
  a.hit = hit;
  if (hit) a.t = ray.tfar, a.u = h.u, a.v = h.v, a.Ng = h.Ng, a.primID = h.primID;
  return a;
}

void expectSame(const Answer& packet, const Answer& alone, const std::string& where) {
  ASSERT_EQ(packet.hit, alone.hit) << where;
  if (!alone.hit) return;
  EXPECT_EQ(packet.t, alone.t) << where;
  EXPECT_EQ(packet.primID, alone.primID) << where;
  EXPECT_EQ(packet.u, alone.u) << where;
  EXPECT_EQ(packet.v, alone.v) << where;
  EXPECT_EQ(packet.Ng.x, alone.Ng.x) << where;
  EXPECT_EQ(packet.Ng.y, alone.Ng.y) << where;
  EXPECT_EQ(packet.Ng.z, alone.Ng.z) << where;
}

// Each packet under several active masks; some lanes get an empty or a shortened segment.
void expectPacketsAnswerAsRaysAlone(const char* preset, AccelLayout layout, int palette) {
  const auto scene = buildStack(preset, layout, palette);
  const std::vector<Ray> rays = packetRays(scene->bounds);
  const QueryState state;
  const uint32_t masks[] = {0xFFFFu, 0x00FFu, 0xA5C3u, 0x8001u, 0x0100u, 0xFFFFu, 0xFFFFu};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  size_t hits = 0, occluded = 0;
  for (size_t first = 0; first + kMaxPacketSize <= rays.size(); first += kMaxPacketSize)
    for (int variant = 0; variant < 7; ++variant) {
      Ray packet[kMaxPacketSize];
      Hit packetHits[kMaxPacketSize];
      for (int r = 0; r < kMaxPacketSize; ++r) {
        packet[r] = rays[first + size_t(r)];
        if (variant == 1 && r % 5 == 2) packet[r].tnear = 1.f, packet[r].tfar = 0.f;  // empty
        if (variant == 2 && r % 3 == 0) packet[r].tfar = 0.5f * (scene->bounds.upper.z - scene->bounds.lower.z);
        if (variant == 3 && r % 4 == 1) packet[r].tnear = 0.25f * (scene->bounds.upper.z - scene->bounds.lower.z);
        if (variant == 5 && r == 3) packet[r].org.y = nan;  // one ray without numbers among coherent ones
        if (variant == 5 && r == 9) packet[r].tfar = nan;
        if (variant == 6) {
          // Down the stack's side plane with a denormal sideways component, whose inverse
          // overflows: each ray is inside the boxes that plane bounds, as if it did not move.
          packet[r].org.x = scene->bounds.lower.x;
          packet[r].dir = {1e-40f, 0.01f * float(r % 4 + 1), -1.f};
        }
        packetHits[r].primID = 0xDEADu;
      }
      const uint32_t active = masks[variant];
      Ray closest[kMaxPacketSize];
      std::copy(packet, packet + kMaxPacketSize, closest);
      const uint32_t found = scene->accel.intersectPacket(closest, packetHits, active, state);
      const uint32_t blocked = scene->accel.occludedPacket(packet, active, state);
      for (int r = 0; r < kMaxPacketSize; ++r) {
        const std::string where = std::string(preset) + " palette " + std::to_string(palette) + " packet " +
                                  std::to_string(first / kMaxPacketSize) + " variant " + std::to_string(variant) +
                                  " lane " + std::to_string(r);
        if (!((active >> r) & 1)) {
          EXPECT_EQ(packetHits[r].primID, 0xDEADu) << where;
          EXPECT_EQ(closest[r].tfar, packet[r].tfar) << where;
          EXPECT_FALSE((found >> r) & 1) << where;
          EXPECT_FALSE((blocked >> r) & 1) << where;
          continue;
        }
        Ray alone = packet[r];
        Hit aloneHit;
        const bool hit = scene->accel.intersect(alone, aloneHit, state);
        expectSame(answerOf((found >> r) & 1, closest[r], packetHits[r]), answerOf(hit, alone, aloneHit), where);
        EXPECT_EQ(bool((blocked >> r) & 1), scene->accel.occluded(packet[r], state)) << where;
        hits += hit;
        occluded += (blocked >> r) & 1;
      }
    }
  EXPECT_GT(hits, 1000u) << preset;
  EXPECT_GT(occluded, 1000u) << preset;
}

TEST(OrientedPackets, AnswerAsTheRaysAlone) {
  if (!simd::cpuHasAvx2()) GTEST_SKIP() << "eight-wide oriented nodes need AVX2";
  for (const char* preset : {"small-1.5k", "stepped-6.6k", "mixed-6.9k"}) {
    expectPacketsAnswerAsRaysAlone(preset, AccelLayout::Obb, 0);
    expectPacketsAnswerAsRaysAlone(preset, AccelLayout::Obb, 7);
    expectPacketsAnswerAsRaysAlone(preset, AccelLayout::Hybrid, 7);
  }
}

}  // namespace
}  // namespace obvh
