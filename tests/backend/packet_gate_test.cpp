// A packet's first test (traversal/packet_gate.h): the lanes it turns away hit nothing, in the hard
// cases of a slab test (origins on the box's planes, directions of +-0 and denormal components, a
// box of zero thickness, segments ending on a face, tnear of -0), in the SSE lanes and the scalar
// reference alike; and it does turn away rays that miss the box.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "backend_mesh_desc.h"
#include "builders/binned_sah_builder.h"
#include "bvh/wide_bvh.h"
#include "scene/primitive_collection.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "test_scenes.h"
#include "traversal/packet_gate.h"
#include "traversal/wide_traversal.h"

namespace obvh {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// An eight-wide tree over the mesh and its packet gate.
struct GatedTree {
  CollectedPrimitives collected;
  WideBvh<8> wide;
  StoredTriangles triangles;
  std::vector<uint32_t> masks{0xFFFFFFFFu};
  TriangleWideView<8> view;
  PacketGate gate;

  explicit GatedTree(const test::MeshData& mesh) {
    collected = collectPrimitives({tools::backendMeshDesc(mesh)});
    const BinaryBvh binary = buildBinnedSah(collected.refs, BuildOptions{});
    for (uint32_t index : binary.primIndices) triangles.push_back(collected.triangles[index]);
    wide = collapseToWide<8>(binary, triangles.data());
    view = makeWideView(wide, TriangleSet{triangles.data(), masks.data(), nullptr, nullptr, nullptr, false});
    gate = queryEntry(view).packetGate;
  }
};

// The lanes of rays[0..count) the gate turns away, from the scalar lanes; the SSE lanes (in fours)
// must agree.
int missingLanes(const PacketGate& gate, const Ray* rays, int count) {
  const auto lanesOf = [&](auto lane, int first) {
    using F = decltype(lane);
    F org[3], dir[3];
    for (int axis = 0; axis < 3; ++axis) {
      org[axis] = F::fromLanes([&](int i) { return first + i < count ? rays[first + i].org[axis] : 0.f; });
      dir[axis] = F::fromLanes([&](int i) { return first + i < count ? rays[first + i].dir[axis] : 1.f; });
    }
    const F tnear = F::fromLanes([&](int i) { return first + i < count ? rays[first + i].tnear : 0.f; });
    const F tfar = F::fromLanes([&](int i) { return first + i < count ? rays[first + i].tfar : 0.f; });
    const int used = count - first >= F::kWidth ? (1 << F::kWidth) - 1 : (1 << (count - first)) - 1;
    return lanesMissingGate(gate, org, dir, tnear, tfar, used);
  };
  const int scalar = lanesOf(simd::FloatScalar<8>{}, 0);
  const int sse = lanesOf(simd::Float4Sse{}, 0) | (count > 4 ? lanesOf(simd::Float4Sse{}, 4) << 4 : 0);
  EXPECT_EQ(scalar, sse);
  return scalar;
}

// Coordinates that put a ray on the box's planes, just beside them, inside and outside.
float coordinateNear(float lower, float upper, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const float span = std::max(upper - lower, 1.f);
  switch (rng() % 7) {
    case 0: return lower;
    case 1: return upper;
    case 2: return std::nextafter(lower, -kInf);
    case 3: return std::nextafter(upper, kInf);
    case 4: return lower + unit(rng) * (upper - lower);
    case 5: return lower - span * unit(rng);
    default: return upper + span * unit(rng);
  }
}

float directionComponent(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  switch (rng() % 6) {
    case 0: return 0.f;
    case 1: return -0.f;
    case 2: return 1e-7f * unit(rng);
    default: return unit(rng);
  }
}

// Every ray the gate turns away misses every triangle (the single ray's walk finds no hit), over
// rays aimed at the mesh's box from on and around its planes; some rays are turned away, and some
// of those let through hit.
void expectTurnedAwayRaysHitNothing(const test::MeshData& mesh, uint32_t seed, int leastHits) {
  GatedTree tree(mesh);
  ASSERT_TRUE(tree.gate.bounded);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const QueryState state;
  int turnedAway = 0, hits = 0;
  for (int packet = 0; packet < 4000; ++packet) {
    Ray rays[8];
    for (Ray& ray : rays) {
      for (int axis = 0; axis < 3; ++axis) {
        ray.org[axis] = coordinateNear(tree.gate.lower[axis], tree.gate.upper[axis], rng);
        // Half the rays aim at a point of the box, so that many hit.
        const float target = coordinateNear(tree.gate.lower[axis], tree.gate.upper[axis], rng);
        ray.dir[axis] = rng() % 2 ? directionComponent(rng) : target - ray.org[axis];
      }
      const int limits = int(rng() % 5);
      ray.tnear = limits == 0 ? -0.f : limits == 1 ? unit(rng) : 0.f;
      ray.tfar = limits == 2 ? unit(rng) * 2.f : limits == 3 ? 1.f : kInf;
    }
    const int missing = missingLanes(tree.gate, rays, 8);
    for (int r = 0; r < 8; ++r) {
      Ray single = rays[r];
      Hit hit;
      const bool hitsSomething = intersectClosestWide(tree.view, single, hit, state, KernelIsa::Scalar);
      hits += hitsSomething;
      if (!((missing >> r) & 1)) continue;
      ++turnedAway;
      ASSERT_FALSE(hitsSomething) << "packet " << packet << " lane " << r << ": org (" << rays[r].org.x << ", "
                                  << rays[r].org.y << ", " << rays[r].org.z << ") dir (" << rays[r].dir.x << ", "
                                  << rays[r].dir.y << ", " << rays[r].dir.z << ") tnear " << rays[r].tnear
                                  << " tfar " << rays[r].tfar;
    }
  }
  EXPECT_GT(turnedAway, 4000);
  EXPECT_GT(hits, leastHits);
}

TEST(PacketGate, TurnedAwayRaysHitNothingOnACube) {
  const float lower[3] = {-1.f, -2.f, 0.5f}, upper[3] = {1.f, 3.f, 0.75f};
  expectTurnedAwayRaysHitNothing(test::cubeGrid(6, lower, upper), 5, 4000);
}

// A flat grid: the box has no thickness along z, and rays in its plane do not move along z.
TEST(PacketGate, TurnedAwayRaysHitNothingOnAFlatGrid) { expectTurnedAwayRaysHitNothing(test::quadGrid(24, 0.f, 3), 9, 600); }

TEST(PacketGate, TurnsAwayRaysThatMissAndKeepsOthers) {
  const float lower[3] = {0.f, 0.f, 0.f}, upper[3] = {1.f, 1.f, 1.f};
  GatedTree tree(test::cubeGrid(4, lower, upper));
  const Ray rays[8] = {
      rayAlong({0.5f, 0.5f, 3.f}, {0.01f, 0.01f, -1.f}),             // down onto it
      rayAlong({1.5f, 0.5f, 3.f}, {0.1f, 0.1f, -1.f}),               // beside it
      rayAlong({0.5f, 0.5f, 3.f}, {0.01f, 0.01f, 1.f}),              // the box behind the origin
      rayAlong({0.5f, 0.5f, 3.f}, {0.01f, 0.01f, -1.f}, 0.f, 1.5f),  // the segment ends short
      rayAlong({0.5f, 1.f, 3.f}, {0.f, 0.f, -1.f}),                  // not moving along x, y, onto a face's edge
      rayAlong({0.5f, 0.5f, 3.f}, {0.01f, 0.01f, -1.f}, -0.f),       // tnear -0: another form, kept
      rayAlong({-2.f, 0.5f, 0.5f}, {1.f, 1.f, 0.f}),                 // passes above an edge
      rayAlong({1.5f, 0.5f, 3.f}, {0.f, 0.f, -1.f}),                 // beside it, not moving along x, y
  };
  EXPECT_EQ(missingLanes(tree.gate, rays, 8), 0b11001110);
}

// A tree whose root is a leaf has no box to test against: nothing is turned away.
TEST(PacketGate, LeafRootTurnsNothingAway) {
  GatedTree tree(test::triangleFan(3));
  EXPECT_FALSE(tree.gate.bounded);
  const Ray away = rayAlong({5.f, 5.f, 5.f}, {1.f, 0.5f, 0.25f});
  const Ray rays[8] = {away, away, away, away, away, away, away, away};
  EXPECT_EQ(missingLanes(tree.gate, rays, 8), 0);
}

}  // namespace
}  // namespace obvh
