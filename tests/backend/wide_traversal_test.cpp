// The wide layouts (bvh4, bvh8): structural checks of the collapse and the triangle blocks, and
// the SIMD kernels against the scalar reference kernels and against the binary BVH, ray by ray
// (bit-identical answers expected).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "builders/binned_sah_builder.h"
#include "bvh/tree_statistics.h"
#include "bvh/wide_bvh.h"
#include "math/float_steps.h"
#include "scene/primitive_collection.h"
#include "simd/cpu_features.h"
#include "backend_mesh_desc.h"
#include "float_bits.h"
#include "test_scenes.h"
#include "traversal/bvh2_traversal.h"
#include "simd/float_scalar.h"
#include "traversal/wide_traversal.h"
#include "traversal/wide_traverse.h"
#include "traversal/wide_traverse_packets.h"

namespace obvh {
namespace {

template <int N>
struct Layouts {
  CollectedPrimitives collected;
  BinaryBvh binary;
  WideBvh<N> wide;
  StoredTriangles triangles;
  std::vector<uint32_t> masks{0xFFFFFFFFu};
  TriangleBvhView view2;
  TriangleWideView<N> view;

  Layouts(const test::MeshData& mesh, int maxLeafSize, bool fast = false, CollapseOptions collapse = {}) {
    collected = collectPrimitives({tools::backendMeshDesc(mesh)});
    BuildOptions options;
    options.maxLeafSize = maxLeafSize;
    binary = buildBinnedSah(collected.refs, options);
    for (uint32_t index : binary.primIndices) triangles.push_back(collected.triangles[index]);
    wide = collapseToWide<N>(binary, triangles.data(), collapse);
    const TriangleSet set{triangles.data(), masks.data(), nullptr, nullptr, nullptr, fast};
    view2 = {binary.nodes.data(), set};
    view = makeWideView(wide, set);
  }
};

// Counts the triangles the leaves reference and checks each block lane against its triangle.
template <int N>
void checkLeaves(const Layouts<N>& l, uint32_t child, std::vector<int>& seen) {
  using Node = WideNode<N>;
  if (child == Node::kEmptyChild) return;
  if (Node::isLeaf(child)) {
    for (uint32_t b = Node::leafFirstBlock(child); b < Node::leafFirstBlock(child) + Node::leafBlockCount(child); ++b)
      for (int lane = 0; lane < 4; ++lane) {
        const TriangleBlock4& block = l.wide.blocks[b];
        if (block.geomID[lane] == TriangleBlock4::kUnusedLane) continue;
        // Soup triangles are one geometry, primID indexes the collected triangles.
        const StoredTriangle tri = block.triangle(lane);
        seen[tri.primID]++;
        const StoredTriangle& expected = l.collected.triangles[tri.primID];
        EXPECT_EQ(tri.v0.x, expected.v0.x);
        EXPECT_EQ(tri.v1.y, expected.v1.y);
        EXPECT_EQ(tri.v2.z, expected.v2.z);
      }
    return;
  }
  for (uint32_t c : l.wide.nodes[child].child) checkLeaves(l, c, seen);
}

template <int N>
void expectEveryTriangleOnce(const Layouts<N>& l) {
  std::vector<int> seen(l.triangles.size(), 0);
  checkLeaves(l, l.wide.rootChild, seen);
  for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "triangle " << i;
}

template <int N>
void expectCollapseKeepsEveryTriangleOnce(int maxLeafSize) {
  Layouts<N> l(test::randomTriangleSoup(20000, 1), maxLeafSize);
  expectEveryTriangleOnce(l);
  size_t used = 0;
  for (const WideNode<N>& node : l.wide.nodes)
    for (uint32_t c : node.child) used += c != WideNode<N>::kEmptyChild;
  // Slots stay empty only where a binary child was already a leaf.
  EXPECT_GT(double(used) / double(N * l.wide.nodes.size()), N == 4 ? 0.75 : 0.5);
  EXPECT_LT(l.wide.nodes.size(), l.binary.nodes.size() / (N / 2));
}

TEST(WideBvh, CollapseKeepsEveryTriangleOnceAndFillsNodes) {
  expectCollapseKeepsEveryTriangleOnce<4>(4);
  expectCollapseKeepsEveryTriangleOnce<4>(7);  // leaves of two blocks, the second one padded
  expectCollapseKeepsEveryTriangleOnce<8>(4);
  expectCollapseKeepsEveryTriangleOnce<8>(13);
}

CollapseOptions sahCollapse(uint32_t maxLeafPrims) {
  CollapseOptions options;
  options.method = CollapseMethod::SahOptimal;
  options.maxLeafPrims = maxLeafPrims;
  return options;
}

// The greedy collapse's tree is among the SAH collapse's candidates: the dynamic programme may
// only lower the cost. With one-triangle binary leaves it must also merge them into fuller blocks.
template <int N>
void expectSahCollapseBeatsGreedy(int binaryLeafSize, uint32_t maxLeafPrims) {
  const test::MeshData soup = test::randomTriangleSoup(20000, 1);
  Layouts<N> greedy(soup, binaryLeafSize);
  Layouts<N> optimal(soup, binaryLeafSize, false, sahCollapse(maxLeafPrims));
  expectEveryTriangleOnce(optimal);
  const double greedySah = statisticsSah(greedy.wide), optimalSah = statisticsSah(optimal.wide);
  EXPECT_LT(optimalSah, greedySah) << "width " << N << ", binary leaves of " << binaryLeafSize;
  EXPECT_LT(optimal.wide.nodes.size(), greedy.wide.nodes.size());
  if (binaryLeafSize == 1) {
    EXPECT_LT(optimal.wide.blocks.size(), greedy.wide.blocks.size() * 3 / 4);
  }
}

TEST(WideBvh, SahCollapseCostsLessThanGreedyAndMergesSmallLeaves) {
  expectSahCollapseBeatsGreedy<4>(4, 28);
  expectSahCollapseBeatsGreedy<8>(4, 28);
  expectSahCollapseBeatsGreedy<8>(1, 4);
  expectSahCollapseBeatsGreedy<4>(1, 8);
}

std::vector<Ray> testRays(uint32_t seed, size_t count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-0.5f, 1.5f);
  std::vector<Ray> rays;
  for (size_t i = 0; i < count; ++i) {
    Ray ray;
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.dir = Vec3f{unit(rng), unit(rng), unit(rng)} - ray.org;
    if (i % 7 == 0) ray.dir[int(i % 3)] = 0.f;                   // a zero component
    if (i % 11 == 0) ray.dir = {0.f, 0.f, i % 2 ? 1.f : -1.f};  // axis-parallel
    if (i % 13 == 0) ray.tnear = 0.3f;
    ray.tfar = i % 17 == 0 ? 0.8f : std::numeric_limits<float>::infinity();
    rays.push_back(ray);
  }
  return rays;
}

// Every kernel of width N (scalar, and SIMD where the CPU has it) answers the ray exactly as the
// binary tree does, and so does its walk for rays declared coherent; returns whether the binary
// tree found a hit.
template <int N>
bool expectKernelsAnswerLikeTheBinaryTree(const Layouts<N>& l, const Ray& ray) {
  std::vector<KernelIsa> kernels = {KernelIsa::Scalar};
  if (bestKernelIsa(N) == KernelIsa::Simd) kernels.push_back(KernelIsa::Simd);
  Ray r2 = ray;
  Hit h2;
  const bool f2 = intersectClosest(l.view2, r2, h2, QueryState());
  const bool any2 = intersectAny(l.view2, ray, QueryState());
  for (const bool coherent : {false, true}) {
    QueryState state;
    state.coherent = coherent;
    for (KernelIsa isa : kernels) {
      EXPECT_EQ(intersectAnyWide(l.view, ray, state, isa), any2) << "isa " << int(isa) << " coherent " << coherent;
      // Closest hits in either child order (device config child_order).
      for (ChildOrder order : {ChildOrder::NearToFar, ChildOrder::Fixed}) {
        Ray r = ray;
        Hit h;
        EXPECT_EQ(intersectClosestWide(l.view, r, h, state, wideKernels<N>(isa, order)), f2)
            << "width " << N << " isa " << int(isa) << " order " << int(order) << " coherent " << coherent;
        if (!f2) continue;
        EXPECT_EQ(r.tfar, r2.tfar);
        EXPECT_EQ(h.primID, h2.primID) << "order " << int(order) << " coherent " << coherent;
        EXPECT_EQ(h.u, h2.u);
        EXPECT_EQ(h.v, h2.v);
        EXPECT_EQ(h.Ng.x, h2.Ng.x);
      }
    }
  }
  return f2;
}

// The binary tree's answer (scalar triangle test per triangle) is the reference for every kernel.
// Both collapses; the SAH collapse may merge binary leaves into leaves of up to 28 triangles.
template <int N>
void expectKernelsMatchBinaryTree(const test::MeshData& mesh, int maxLeafSize, bool fast, uint32_t seed,
                                  size_t minHits) {
  for (const CollapseOptions& collapse : {CollapseOptions{}, sahCollapse(28)}) {
    Layouts<N> l(mesh, maxLeafSize, fast, collapse);
    size_t hits = 0;
    for (const Ray& ray : testRays(seed, 20000)) hits += expectKernelsAnswerLikeTheBinaryTree(l, ray);
    EXPECT_GT(hits, minHits);
  }
}

TEST(WideBvh, KernelsMatchTheBinaryTreeOnATriangleSoup) {
  if (bestKernelIsa(4) == KernelIsa::Scalar) std::printf("no SSE4.2 here: only the scalar bvh4 kernel is compared\n");
  if (bestKernelIsa(8) == KernelIsa::Scalar) std::printf("no AVX2 here: only the scalar bvh8 kernel is compared\n");
  const test::MeshData soup = test::randomTriangleSoup(5000, 2);
  expectKernelsMatchBinaryTree<4>(soup, 6, false, 3, 3000);
  expectKernelsMatchBinaryTree<8>(soup, 6, false, 3, 3000);
  expectKernelsMatchBinaryTree<4>(soup, 3, true, 4, 3000);  // intersector=fast: Moeller-Trumbore in SIMD
  expectKernelsMatchBinaryTree<8>(soup, 3, true, 4, 3000);
}

TEST(WideBvh, KernelsMatchTheBinaryTreeOnSharedEdges) {
  // A jittered quad grid: rays through shared edges and vertices take the zero-edge-function path.
  const test::MeshData grid = test::quadGrid(40, 0.3f, 4);
  expectKernelsMatchBinaryTree<4>(grid, 4, false, 5, 1000);
  expectKernelsMatchBinaryTree<8>(grid, 4, false, 5, 1000);
  expectKernelsMatchBinaryTree<4>(grid, 4, true, 6, 1000);
  expectKernelsMatchBinaryTree<8>(grid, 4, true, 6, 1000);
}

// Denormal direction components overflow 1/dir; the binary tree's box test rounds those slabs
// differently, so here the SIMD kernels are compared with their scalar reference only.
template <int N>
void expectSimdMatchesScalarOnDenormalDirections() {
  if (bestKernelIsa(N) == KernelIsa::Scalar) return;
  Layouts<N> l(test::randomTriangleSoup(3000, 7), 4);
  const QueryState state;
  size_t hits = 0;
  std::vector<Ray> rays = testRays(8, 6000);
  for (size_t i = 0; i < rays.size(); ++i) {
    Ray ray = rays[i];
    ray.dir[int(i % 3)] = i % 2 ? 1e-40f : -1e-40f;
    Ray rs = ray, rv = ray;
    Hit hs, hv;
    const bool fs = intersectClosestWide(l.view, rs, hs, state, KernelIsa::Scalar);
    ASSERT_EQ(intersectClosestWide(l.view, rv, hv, state, KernelIsa::Simd), fs);
    hits += fs;
    if (fs) {
      EXPECT_EQ(rs.tfar, rv.tfar);
      EXPECT_EQ(hs.primID, hv.primID);
    }
    EXPECT_EQ(intersectAnyWide(l.view, ray, state, KernelIsa::Scalar), intersectAnyWide(l.view, ray, state, KernelIsa::Simd));
  }
  EXPECT_GT(hits, 100u);
}

TEST(WideBvh, SimdMatchesScalarOnDenormalDirections) {
  expectSimdMatchesScalarOnDenormalDirections<4>();
  expectSimdMatchesScalarOnDenormalDirections<8>();
}

// Vertical walls (along x, along y and diagonal) over a floor, traced straight down on a grid
// that puts many rays exactly in a wall's plane: the SIMD kernels skip the double-precision
// recheck for triangles whose vertices coincide in the ray's frame, and must still answer exactly
// as the scalar test and the binary tree do.
test::MeshData wallsSeenEdgeOn() {
  test::MeshData mesh;
  auto quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d) {
    const uint32_t base = uint32_t(mesh.vertices.size() / 3);
    for (const Vec3f& p : {a, b, c, d}) mesh.vertices.insert(mesh.vertices.end(), {p.x, p.y, p.z});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  };
  for (int i = 0; i < 16; ++i) {
    const float w = 0.25f + 0.5f * float(i);
    quad({w, 0.f, 0.f}, {w, 8.f, 0.f}, {w, 8.f, 1.f}, {w, 0.f, 1.f});            // x = w
    quad({0.f, w, 0.f}, {8.f, w, 0.f}, {8.f, w, 1.5f}, {0.f, w, 1.5f});          // y = w
    quad({w, 0.f, 0.f}, {w + 2.f, 2.f, 0.f}, {w + 2.f, 2.f, 2.f}, {w, 0.f, 2.f});  // diagonal
  }
  quad({-1.f, -1.f, -0.5f}, {9.f, -1.f, -0.5f}, {9.f, 9.f, -0.5f}, {-1.f, 9.f, -0.5f});  // floor
  return mesh;
}

template <int N>
void expectWallsSeenEdgeOnMatchTheBinaryTree(CollapseOptions collapse) {
  Layouts<N> l(wallsSeenEdgeOn(), 4, false, collapse);
  size_t inWallPlane = 0, hits = 0;
  for (int i = 0; i <= 64; ++i)
    for (int j = 0; j <= 64; ++j) {
      Ray ray;
      ray.org = {0.125f * float(i), 0.125f * float(j), 5.f};  // exact: walls sit at 0.125 * (2 + 4k)
      ray.dir = {0.f, 0.f, (i + j) % 2 ? -1.f : -2.f};
      ray.tfar = std::numeric_limits<float>::infinity();
      inWallPlane += i % 4 == 2 || j % 4 == 2 || ((i - j) % 4 + 4) % 4 == 2;
      hits += expectKernelsAnswerLikeTheBinaryTree(l, ray);
    }
  EXPECT_GT(inWallPlane, 2000u);
  EXPECT_EQ(hits, 65u * 65u);  // the floor below everything
}

TEST(WideBvh, WallsSeenEdgeOnMatchTheBinaryTree) {
  for (const CollapseOptions& collapse : {CollapseOptions{}, sahCollapse(28)}) {
    expectWallsSeenEdgeOnMatchTheBinaryTree<4>(collapse);
    expectWallsSeenEdgeOnMatchTheBinaryTree<8>(collapse);
  }
}

// Segments that end exactly where a face is hit, or just before it, or that are empty (tfar +0 or
// -0 with tnear +0, tfar below tnear): the node tests' exit limit (the integer forms lower tfar by
// their far ulps and compare against the entry lowered by one more) must keep a box whose entry is
// exactly tfar and enter nothing for a negative tfar. Horizontal layers traced straight down (the
// entry distance of a layer's flat box is exactly the hit distance) and slightly tilted (every
// axis moving: the other integer form).
template <int N>
void expectSegmentEndsMatchTheBinaryTree() {
  test::MeshData layers;
  for (int k = 0; k < 12; ++k) {
    const float z = 0.5f * float(k);
    const uint32_t base = uint32_t(layers.vertices.size() / 3);
    for (const Vec3f& p : {Vec3f{0.f, 0.f, z}, Vec3f{8.f, 0.f, z}, Vec3f{8.f, 8.f, z}, Vec3f{0.f, 8.f, z}})
      layers.vertices.insert(layers.vertices.end(), {p.x, p.y, p.z});
    layers.indices.insert(layers.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  }
  Layouts<N> l(layers, 2);
  const QueryState state;
  size_t boundaryHits = 0;
  for (int i = 1; i < 16; ++i)
    for (int tilt = 0; tilt < 2; ++tilt) {
      Ray ray;
      ray.org = {0.5f * float(i), 0.25f * float(i), 7.f};
      ray.dir = tilt ? Vec3f{1e-3f, -2e-3f, -1.f} : Vec3f{0.f, 0.f, -1.f};
      ray.tfar = std::numeric_limits<float>::infinity();
      Ray probe = ray;
      Hit hit;
      ASSERT_TRUE(intersectClosest(l.view2, probe, hit, state));
      const float t = probe.tfar;
      for (float tfar : {t, nextFloatDown(t), 0.f, -0.f, std::numeric_limits<float>::denorm_min(), -1.f}) {
        Ray segment = ray;
        segment.tfar = tfar;
        boundaryHits += expectKernelsAnswerLikeTheBinaryTree(l, segment) && tfar == t;
      }
      Ray behind = ray;  // tnear beyond the first layer: the next one down
      behind.tnear = t;
      expectKernelsAnswerLikeTheBinaryTree(l, behind);
    }
  EXPECT_EQ(boundaryHits, 30u);  // every ray still finds its face with tfar exactly at it
}

TEST(WideBvh, SegmentEndsMatchTheBinaryTree) {
  expectSegmentEndsMatchTheBinaryTree<4>();
  expectSegmentEndsMatchTheBinaryTree<8>();
}

// Whether primitive primID reports distance t for the ray too: a packet, which visits leaves in its
// own order, may report either of two primitives that tie at the closest distance.
template <int N>
bool hitsAtDistance(const Layouts<N>& l, const Ray& ray, uint32_t primID, float t) {
  bool reproduced = false;
  for (const StoredTriangle& tri : l.triangles) {
    if (tri.primID != primID) continue;
    Ray probe = ray;
    probe.tfar = std::numeric_limits<float>::infinity();
    TriangleHit th;
    reproduced |= intersectWatertight(WatertightRay(probe), probe, tri.v0, tri.v1, tri.v2, th) && th.t == t;
  }
  return reproduced;
}

// Packets of up to 16 rays (partial masks, coherent and incoherent lanes) find the same closest
// distance and occlusion as each ray alone. The hit primitive may differ only where two
// primitives tie at that distance (the packet visits leaves in its own order).
template <int N>
void expectPacketsMatchSingleRays(KernelIsa isa) {
  Layouts<N> l(test::quadGrid(40, 0.3f, 11), 4);
  const QueryState state;
  const std::vector<Ray> pool = testRays(12, 16 * 400);
  size_t hits = 0;
  for (size_t p = 0; p < pool.size() / 16; ++p) {
    Ray rays[kMaxPacketSize];
    Hit packetHits[kMaxPacketSize];
    const uint32_t active = p % 3 == 0 ? 0xFFFFu : uint32_t(0x5A5Bu ^ p) & 0xFFFFu;
    for (int r = 0; r < 16; ++r) {
      rays[r] = pool[p * 16 + r];
      // A common origin: coherent lanes; every eighth packet keeps its rays' own origins with one
      // direction sign per axis (below), as shadow rays from neighbouring hits have, which tests the
      // packet's origin bounds (PacketLanes::mayEnter).
      if (p % 2 && p % 8 != 5) rays[r].org = pool[p * 16].org;
      if (p % 4 == 1) {
        // Also one sign per axis and no zero component, like a camera's rays: the packet then
        // tests each child box against its rays as SIMD lanes (PacketLanes).
        const Vec3f d = pool[p * 16 + r].dir;
        const float sign[3] = {p & 4 ? -1.f : 1.f, p & 8 ? -1.f : 1.f, p & 16 ? -1.f : 1.f};
        for (int axis = 0; axis < 3; ++axis) rays[r].dir[axis] = sign[axis] * (0.05f + std::fabs(d[axis]));
      }
      if (p % 4 == 3) {
        // One dominant axis and sign for every ray, as a camera's rays have: the packet's leaves
        // then also test two rays against each block at once (triangle_block_pairs.h).
        const Vec3f first = pool[p * 16].dir;
        int dominant = 0;
        for (int axis = 1; axis < 3; ++axis)
          if (std::fabs(first[axis]) > std::fabs(first[dominant])) dominant = axis;
        const Vec3f d = pool[p * 16 + r].dir;
        for (int axis = 0; axis < 3; ++axis)
          rays[r].dir[axis] = axis == dominant ? std::copysign(1.f, first[axis]) : 0.5f * d[axis] / (std::fabs(d[axis]) + 1.f);
      }
    }
    Ray packetRays[kMaxPacketSize];
    std::copy(rays, rays + 16, packetRays);
    const uint32_t found = intersectClosestWidePacket(l.view, packetRays, packetHits, active, state, isa);
    const uint32_t occluded = intersectAnyWidePacket(l.view, rays, active, state, isa);
    for (int r = 0; r < 16; ++r) {
      const bool on = (active >> r) & 1;
      Ray single = rays[r];
      Hit hit;
      const bool f = on && intersectClosestWide(l.view, single, hit, state, isa);
      ASSERT_EQ(bool((found >> r) & 1), f) << "packet " << p << " lane " << r;
      EXPECT_EQ(bool((occluded >> r) & 1), on && intersectAnyWide(l.view, rays[r], state, isa));
      if (!on) {
        EXPECT_EQ(packetRays[r].tfar, rays[r].tfar);  // inactive lanes untouched
      }
      if (!f) continue;
      ++hits;
      EXPECT_EQ(packetRays[r].tfar, single.tfar);
      if (packetHits[r].primID != hit.primID) {
        EXPECT_TRUE(hitsAtDistance(l, rays[r], packetHits[r].primID, single.tfar))
            << "packet " << p << " lane " << r << ": primID " << packetHits[r].primID << " vs " << hit.primID;
      }
    }
  }
  EXPECT_GT(hits, 300u);
}

// Packets whose rays share their direction signs but start far apart (shadow rays from hits
// spread over a surface towards one light): every box some ray enters must pass the packet's
// bounds test (PacketLanes::mayEnter, built from the rays' origin and 1/dir ranges).
template <int N>
void expectSpreadOriginPacketsMatchSingleRays(KernelIsa isa) {
  Layouts<N> l(test::quadGrid(40, 0.3f, 11), 4);
  Box3f box;
  for (const StoredTriangle& tri : l.triangles) box.extend(tri.v0), box.extend(tri.v1), box.extend(tri.v2);
  const Vec3f extent = box.upper - box.lower;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const QueryState state;
  size_t hits = 0, occluded = 0;
  for (int p = 0; p < 600; ++p) {
    // A light beyond one corner of the scene, so that every ray's direction has one sign per axis.
    Vec3f light;
    for (int axis = 0; axis < 3; ++axis)
      light[axis] = p & (1 << axis) ? box.upper[axis] + extent[axis] : box.lower[axis] - extent[axis];
    Ray rays[kMaxPacketSize];
    for (int r = 0; r < 16; ++r) {
      for (int axis = 0; axis < 3; ++axis) rays[r].org[axis] = box.lower[axis] + unit(rng) * extent[axis];
      rays[r].dir = light - rays[r].org;
      rays[r].tnear = 0.f;
      rays[r].tfar = p % 3 ? 1.f : std::numeric_limits<float>::infinity();
    }
    // Every fourth packet has its first eight lanes idle (a lane group without rays).
    const uint32_t active = p % 4 == 0 ? 0xFF00u : 0xFFFFu;
    Ray packetRays[kMaxPacketSize];
    Hit packetHits[kMaxPacketSize];
    std::copy(rays, rays + 16, packetRays);
    const uint32_t found = intersectClosestWidePacket(l.view, packetRays, packetHits, active, state, isa);
    const uint32_t blocked = intersectAnyWidePacket(l.view, rays, active, state, isa);
    for (int r = 0; r < 16; ++r) {
      if (!((active >> r) & 1)) {
        EXPECT_FALSE(((found | blocked) >> r) & 1) << "packet " << p << " idle lane " << r;
        EXPECT_EQ(packetRays[r].tfar, rays[r].tfar);
        continue;
      }
      Ray single = rays[r];
      Hit hit;
      const bool f = intersectClosestWide(l.view, single, hit, state, isa);
      ASSERT_EQ(bool((found >> r) & 1), f) << "packet " << p << " lane " << r;
      ASSERT_EQ(bool((blocked >> r) & 1), intersectAnyWide(l.view, rays[r], state, isa)) << "packet " << p << " lane " << r;
      if (f) {
        EXPECT_EQ(packetRays[r].tfar, single.tfar) << "packet " << p << " lane " << r;
      }
      hits += f;
      occluded += (blocked >> r) & 1;
    }
  }
  EXPECT_GT(hits, 1000u);
  EXPECT_GT(occluded, 1000u);
}

TEST(WideBvh, PacketsWithSpreadOriginsMatchSingleRays) {
  expectSpreadOriginPacketsMatchSingleRays<4>(KernelIsa::Scalar);
  expectSpreadOriginPacketsMatchSingleRays<8>(KernelIsa::Scalar);
  expectSpreadOriginPacketsMatchSingleRays<4>(bestKernelIsa(4));
  expectSpreadOriginPacketsMatchSingleRays<8>(bestKernelIsa(8));
}

TEST(WideBvh, PacketsMatchSingleRays) {
  expectPacketsMatchSingleRays<4>(KernelIsa::Scalar);
  expectPacketsMatchSingleRays<8>(KernelIsa::Scalar);
  expectPacketsMatchSingleRays<4>(bestKernelIsa(4));
  expectPacketsMatchSingleRays<8>(bestKernelIsa(8));
}

// Orthographic packets (rays that do not move along one or two axes, direction +-0 there) over
// walls seen edge-on, with many rays exactly in a wall's plane, that is on the planes of the boxes
// around it: packets whose rays share their zero axes and sign bits take the packet walk
// (PacketLanes with zeroAxes, the node test's integer form with zero axes), the others go ray by
// ray. Either way every lane answers as the ray alone does, up to which of two primitives at the
// closest distance it reports.
template <int N>
void expectOrthographicPacketsMatchSingleRays(KernelIsa isa) {
  Layouts<N> l(wallsSeenEdgeOn(), 4);
  size_t hits = 0, packetWalks = 0, ties = 0;
  for (int variant = 0; variant < 6; ++variant)
    for (int row = 0; row <= 64; ++row)
      for (int start = 0; start <= 64; start += 16) {
        Ray rays[kMaxPacketSize];
        for (int r = 0; r < 16; ++r) {
          const int i = std::min(start + r, 64);
          rays[r].org = {0.125f * float(i), 0.125f * float(row), 5.f};  // exact: walls sit at 0.125 * (2 + 4k)
          rays[r].tfar = std::numeric_limits<float>::infinity();
          switch (variant) {
            case 0: rays[r].dir = {0.f, 0.f, -1.f}; break;                    // zero axes x, y
            case 1: rays[r].dir = {-0.f, 0.f, -2.f}; break;                   // x's sign bit set
            case 2: rays[r].dir = {0.f, 0.01f * float(r + 1), -1.f}; break;   // zero axis x only
            case 3: rays[r].dir = {r % 2 ? -0.f : 0.f, 0.f, -1.f}; break;     // sign bits differ
            case 4: rays[r].dir = {r % 3 ? 0.f : 0.02f, 0.f, -1.f}; break;    // x zero for some only
            default: rays[r].dir = {0.f, 0.f, 0.f}; break;                    // no axis moving
          }
        }
        const uint32_t active = row % 3 == 0 ? 0xFFFFu : uint32_t(0x6D2Bu >> (row % 5)) & 0xFFFFu;
        const PacketLanes<simd::FloatScalar<N>> lanes(rays, active);
        ASSERT_EQ(lanes.usable, variant < 3) << "variant " << variant;
        if (lanes.usable) {
          EXPECT_EQ(lanes.zeroAxes, variant == 2 ? 1 : 3);
          ++packetWalks;
        }
        Ray packetRays[kMaxPacketSize];
        Hit packetHits[kMaxPacketSize];
        std::copy(rays, rays + 16, packetRays);
        const QueryState state;
        const uint32_t found = intersectClosestWidePacket(l.view, packetRays, packetHits, active, state, isa);
        const uint32_t occluded = intersectAnyWidePacket(l.view, rays, active, state, isa);
        for (int r = 0; r < 16; ++r) {
          if (!((active >> r) & 1)) {
            EXPECT_FALSE(((found | occluded) >> r) & 1);
            EXPECT_EQ(packetRays[r].tfar, rays[r].tfar);
            continue;
          }
          Ray single = rays[r];
          Hit hit;
          const bool f = intersectClosestWide(l.view, single, hit, state, isa);
          ASSERT_EQ(bool((found >> r) & 1), f) << "variant " << variant << " row " << row << " lane " << r;
          EXPECT_EQ(bool((occluded >> r) & 1), intersectAnyWide(l.view, rays[r], state, isa));
          if (!f) continue;
          ++hits;
          EXPECT_TRUE(test::sameBits(packetRays[r].tfar, single.tfar)) << "variant " << variant << " lane " << r;
          if (packetHits[r].primID == hit.primID) {
            EXPECT_EQ(packetHits[r].u, hit.u);
            EXPECT_EQ(packetHits[r].v, hit.v);
          } else {
            ++ties;
            EXPECT_TRUE(hitsAtDistance(l, rays[r], packetHits[r].primID, single.tfar))
                << "variant " << variant << " row " << row << " lane " << r;
          }
        }
      }
  EXPECT_EQ(packetWalks, 3u * 65u * 5u);
  EXPECT_GT(hits, 3u * 65u * 65u);  // the floor below everything, for every variant with a direction
  EXPECT_LT(ties, hits / 100);        // rays in a wall's plane that meet a wall's two triangles
}

TEST(WideBvh, OrthographicPacketsMatchSingleRays) {
  expectOrthographicPacketsMatchSingleRays<4>(KernelIsa::Scalar);
  expectOrthographicPacketsMatchSingleRays<8>(KernelIsa::Scalar);
  expectOrthographicPacketsMatchSingleRays<4>(bestKernelIsa(4));
  expectOrthographicPacketsMatchSingleRays<8>(bestKernelIsa(8));
}

template <int N>
void expectNanRaysHitNothing() {
  Layouts<N> l(test::randomTriangleSoup(500, 6), 4);
  const QueryState state;
  Ray ray;
  ray.org = {std::nanf(""), 0.5f, 0.5f};
  ray.dir = {1.f, 0.f, 0.f};
  ray.tfar = std::numeric_limits<float>::infinity();
  Hit hit;
  for (KernelIsa isa : {KernelIsa::Scalar, bestKernelIsa(N)}) {
    Ray r = ray;
    EXPECT_FALSE(intersectClosestWide(l.view, r, hit, state, isa));
    EXPECT_FALSE(intersectAnyWide(l.view, ray, state, isa));
  }
}

// The counted kernels (heatmaps) answer exactly like the normal ones and count every node they
// test: a ray that hits tests at least the root's boxes and visits a leaf.
template <int N>
void expectCountedKernelsAnswerTheSame() {
  Layouts<N> l(test::randomTriangleSoup(4000, 8), 4);
  for (KernelIsa isa : {KernelIsa::Scalar, bestKernelIsa(N)}) {
    uint64_t totalTests = 0;
    for (const Ray& ray : testRays(9, 3000)) {
      TraversalCounters counters;
      QueryState counted;
      counted.counters = &counters;
      const QueryState plain;
      Ray a = ray, b = ray;
      Hit ha, hb;
      const bool found = intersectClosestWide(l.view, a, ha, plain, isa);
      ASSERT_EQ(intersectClosestWide(l.view, b, hb, counted, isa), found);
      EXPECT_EQ(a.tfar, b.tfar);
      EXPECT_EQ(ha.primID, hb.primID);
      if (found) {
        EXPECT_GE(counters.aabbTests, uint64_t(N));
        EXPECT_EQ(counters.aabbTests % N, 0u);
        EXPECT_GE(counters.leafVisits, 1u);
      }
      totalTests += counters.aabbTests;
      TraversalCounters anyCounters;
      counted.counters = &anyCounters;
      EXPECT_EQ(intersectAnyWide(l.view, ray, counted, isa), intersectAnyWide(l.view, ray, plain, isa));
    }
    EXPECT_GT(totalTests, 3000u * N);
  }
}

TEST(WideBvh, CountedKernelsAnswerTheSame) {
  expectCountedKernelsAnswerTheSame<4>();
  expectCountedKernelsAnswerTheSame<8>();
}

TEST(WideBvh, NanRaysHitNothing) {
  expectNanRaysHitNothing<4>();
  expectNanRaysHitNothing<8>();
}

// The closest-hit kernels' root-box check (missesRootBox) turns a ray away only where the root
// node's own test (the integer form, with the scalar reference lanes) enters none of its children:
// rays from around the scene aimed at points of the box's faces, edges and corners, exactly on them
// and a float to either side, where the children's boxes touch the root box, and rays whose origin
// is not a number. Both answers occur.
template <int N>
void expectRootBoxTurnsAwayOnlyWhatTheRootNodeDoes() {
  using FN = simd::FloatScalar<N>;
  Layouts<N> l(test::randomTriangleSoup(3000, 4), 4);
  const Box3f box = l.wide.rootNodeBox();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::uniform_int_distribution<int> side(0, 2), nudge(-1, 1);
  int turnedAway = 0, admitted = 0;
  for (int i = 0; i < 100000; ++i) {
    Vec3f target, org;
    for (int a = 0; a < 3; ++a) {
      const float lo = box.lower[a], hi = box.upper[a], span = hi - lo;
      // On the lower or upper plane, or anywhere between; then maybe a float off it.
      const int where = side(rng);
      float x = where == 0 ? lo : where == 1 ? hi : lo + unit(rng) * span;
      const int step = nudge(rng);
      if (step != 0) x = std::nextafter(x, step > 0 ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity());
      target[a] = x;
      org[a] = lo - span + 3.f * span * unit(rng);
    }
    Ray ray;
    ray.org = org;
    ray.dir = target - org;
    ray.tnear = 0.f;
    ray.tfar = i % 3 == 0 ? 1.f : std::numeric_limits<float>::infinity();
    // Every fourth ray with an origin not a number along one axis, of either sign: the root-box
    // check does not look for NaN distances, on the grounds that the node test enters no child
    // for such rays.
    if (i % 4 == 1) {
      const float nan = std::numeric_limits<float>::quiet_NaN();
      ray.org[side(rng)] = nudge(rng) < 0 ? -nan : nan;
    }
    // The kernels check the box only for rays whose direction allows the integer form.
    const RayDirection<typename FN::Lanes4> direction(ray);
    const WideRayFrame<FN> frame(ray, direction);
    ASSERT_EQ(direction.integerForm, nodeTestFormOf(frame) == NodeTestForm::kBits) << "ray " << i;
    if (!direction.integerForm) continue;
    const bool misses = missesRootBox<FN>(l.view, ray, direction);
    float entry[N];
    const int entered = intersectWideNode<NodeTestForm::kBits>(
        l.wide.nodes[l.wide.rootChild], frame, exitLimitLanes<NodeTestForm::kBits, FN>(ray.tfar), entry);
    if (i % 4 == 1) {
      ASSERT_EQ(entered, 0) << "ray " << i << " (origin not a number)";
    }
    if (misses) {
      ASSERT_EQ(entered, 0) << "ray " << i;
      ++turnedAway;
    } else {
      ++admitted;
    }
  }
  EXPECT_GT(turnedAway, 1000);
  EXPECT_GT(admitted, 1000);
}

TEST(WideBvh, RootBoxTurnsAwayOnlyWhatTheRootNodeDoes) {
  expectRootBoxTurnsAwayOnlyWhatTheRootNodeDoes<4>();
  expectRootBoxTurnsAwayOnlyWhatTheRootNodeDoes<8>();
}

// The single-ray kernels make the integer form's frame apart (WideRayFrame::ofIntegerForm) for the
// rays RayDirection::integerForm admits, without the frame's checks: those rays must be exactly the
// rays whose frame takes that form, and get the same frame. Directions and tnear from the values
// that decide it: zeros of either sign, denormals, infinities, NaN, negative values.
template <int N>
void expectIntegerFormShortcutMatchesTheFrame() {
  using FN = simd::FloatScalar<N>;
  using test::sameBits;
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float denormal = std::numeric_limits<float>::denorm_min() * 3.f;
  const float components[] = {0.f, -0.f, 1.f, -2.5f, denormal, -denormal, inf, nan, 1e-30f};
  const float tnears[] = {0.f, -0.f, 0.5f, -1.f, nan, inf, std::numeric_limits<float>::max()};
  int shortcut = 0, other = 0;
  for (float x : components)
    for (float y : components)
      for (float z : components)
        for (float tnear : tnears) {
          Ray ray;
          ray.org = Vec3f{0.25f, -3.f, 7.f};
          ray.dir = Vec3f{x, y, z};
          ray.tnear = tnear;
          ray.tfar = inf;
          const RayDirection<typename FN::Lanes4> direction(ray);
          const WideRayFrame<FN> frame(ray, direction);
          ASSERT_EQ(direction.integerForm, nodeTestFormOf(frame) == NodeTestForm::kBits)
              << x << " " << y << " " << z << " tnear " << tnear;
          if (!direction.integerForm) {
            ++other;
            continue;
          }
          ++shortcut;
          const WideRayFrame<FN> made = WideRayFrame<FN>::ofIntegerForm(ray, direction);
          ASSERT_EQ(nodeTestFormOf(made), NodeTestForm::kBits);
          for (int lane = 0; lane < N; ++lane) {
            ASSERT_TRUE(sameBits(made.tnear.v[lane], frame.tnear.v[lane]));
            ASSERT_TRUE(sameBits(made.nearAllowance.v[lane], frame.nearAllowance.v[lane]));
            for (int axis = 0; axis < 3; ++axis) {
              ASSERT_TRUE(sameBits(made.org[axis].v[lane], frame.org[axis].v[lane]));
              ASSERT_TRUE(sameBits(made.negInv[axis].v[lane], frame.negInv[axis].v[lane]));
            }
          }
          for (int axis = 0; axis < 3; ++axis) ASSERT_EQ(made.nearByte[axis], frame.nearByte[axis]);
        }
  // Along each axis 1, -2.5 and 1e-30 (1/dir finite and not zero), and tnear 0, 0.5 and the
  // largest float (-0 has its sign bit set): 3 * 3 * 3 * 3 rays.
  EXPECT_EQ(shortcut, 81);
  EXPECT_GT(other, 100);
}

TEST(WideBvh, IntegerFormShortcutMatchesTheFrame) {
  expectIntegerFormShortcutMatchesTheFrame<4>();
  expectIntegerFormShortcutMatchesTheFrame<8>();
}

}  // namespace
}  // namespace obvh
