// The four-wide layout: structural checks of the collapse, and the SSE kernel against the scalar
// reference kernel and against the binary BVH, ray by ray (bit-identical answers expected).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "builders/binned_sah_builder.h"
#include "bvh/bvh4.h"
#include "scene/primitive_collection.h"
#include "simd/cpu_features.h"
#include "test_scenes.h"
#include "traversal/bvh2_traversal.h"
#include "traversal/bvh4_traversal.h"

namespace obvh {
namespace {

struct Layouts {
  CollectedPrimitives collected;
  BinaryBvh binary;
  Bvh4 wide;
  std::vector<StoredTriangle> triangles;
  std::vector<uint32_t> masks{0xFFFFFFFFu};
  TriangleBvhView view2;
  TriangleBvh4View view4;

  explicit Layouts(const test::MeshData& mesh) {
    MeshDesc desc;
    desc.vertices = reinterpret_cast<const unsigned char*>(mesh.vertices.data());
    desc.vertexStride = 12;
    desc.vertexCount = mesh.vertexCount();
    desc.indices = reinterpret_cast<const unsigned char*>(mesh.indices.data());
    desc.indexStride = mesh.quads ? 16 : 12;
    desc.primCount = mesh.primitiveCount();
    desc.quads = mesh.quads;
    collected = collectPrimitives({desc});
    BuildOptions options;
    options.maxLeafSize = 6;
    binary = buildBinnedSah(collected.refs, options);
    for (uint32_t index : binary.primIndices) triangles.push_back(collected.triangles[index]);
    wide = collapseToBvh4(binary);
    const TriangleSet set{triangles.data(), masks.data(), nullptr, nullptr, nullptr};
    view2 = {binary.nodes.data(), set};
    view4 = {wide.nodes.data(), wide.rootChild, set};
  }
};

void countLeafPrimitives(const Bvh4& bvh, uint32_t child, size_t& prims) {
  if (child == Bvh4Node::kEmptyChild) return;
  if (Bvh4Node::isLeaf(child)) {
    prims += Bvh4Node::leafCount(child);
    return;
  }
  for (uint32_t c : bvh.nodes[child].child) countLeafPrimitives(bvh, c, prims);
}

TEST(Bvh4, CollapseKeepsEveryPrimitiveAndFillsNodes) {
  Layouts l(test::randomTriangleSoup(20000, 1));
  size_t prims = 0;
  countLeafPrimitives(l.wide, l.wide.rootChild, prims);
  EXPECT_EQ(prims, l.triangles.size());
  size_t used = 0;
  for (const Bvh4Node& node : l.wide.nodes)
    for (uint32_t c : node.child) used += c != Bvh4Node::kEmptyChild;
  // Slots stay empty only where a binary child was already a leaf; 80% are used on this soup.
  EXPECT_GT(double(used) / double(4 * l.wide.nodes.size()), 0.75);
  EXPECT_LT(l.wide.nodes.size(), l.binary.nodes.size() / 2);
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

TEST(Bvh4, SseAndScalarKernelsMatchTheBinaryTreeExactly) {
  if (!simd::cpuHasSse42()) GTEST_SKIP() << "this CPU has no SSE4.2; the scalar kernel is compared below";
  Layouts l(test::randomTriangleSoup(5000, 2));
  const QueryState state;
  size_t hits = 0;
  for (const Ray& ray : testRays(3, 30000)) {
    Ray r2 = ray, rs = ray, rv = ray;
    Hit h2, hs, hv;
    const bool f2 = intersectClosest(l.view2, r2, h2, state);
    const bool fs = intersectClosestBvh4(l.view4, rs, hs, state, KernelIsa::Scalar);
    const bool fv = intersectClosestBvh4(l.view4, rv, hv, state, KernelIsa::Sse42);
    ASSERT_EQ(f2, fs);
    ASSERT_EQ(fs, fv);
    hits += f2;
    if (f2) {
      EXPECT_EQ(r2.tfar, rs.tfar);
      EXPECT_EQ(rs.tfar, rv.tfar);
      EXPECT_EQ(hs.primID, hv.primID);
    }
    EXPECT_EQ(intersectAny(l.view2, ray, state), intersectAnyBvh4(l.view4, ray, state, KernelIsa::Scalar));
    EXPECT_EQ(intersectAnyBvh4(l.view4, ray, state, KernelIsa::Scalar),
              intersectAnyBvh4(l.view4, ray, state, KernelIsa::Sse42));
  }
  EXPECT_GT(hits, 3000u);
}

TEST(Bvh4, ScalarKernelMatchesTheBinaryTree) {
  Layouts l(test::quadGrid(40, 0.3f, 4));
  const QueryState state;
  for (const Ray& ray : testRays(5, 20000)) {
    Ray r2 = ray, rs = ray;
    Hit h2, hs;
    ASSERT_EQ(intersectClosest(l.view2, r2, h2, state),
              intersectClosestBvh4(l.view4, rs, hs, state, KernelIsa::Scalar));
    EXPECT_EQ(r2.tfar, rs.tfar);
  }
}

TEST(Bvh4, NanRaysHitNothing) {
  Layouts l(test::randomTriangleSoup(500, 6));
  const QueryState state;
  Ray ray;
  ray.org = {std::nanf(""), 0.5f, 0.5f};
  ray.dir = {1.f, 0.f, 0.f};
  ray.tfar = std::numeric_limits<float>::infinity();
  Hit hit;
  for (KernelIsa isa : {KernelIsa::Scalar, bestKernelIsa()}) {
    Ray r = ray;
    EXPECT_FALSE(intersectClosestBvh4(l.view4, r, hit, state, isa));
    EXPECT_FALSE(intersectAnyBvh4(l.view4, ray, state, isa));
  }
}

}  // namespace
}  // namespace obvh
