// The alternative builders (device config builder=kmeans|distance): well-formed trees, k-means
// finds the clusters a scene has, the distance term pulls primitives near the source up the tree,
// and every layout built by them answers rays like the default binned-SAH build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "builders/binned_sah_builder.h"
#include "builders/distance_sah_builder.h"
#include "builders/kmeans_builder.h"
#include "bvh/oriented_layout.h"
#include "scene/primitive_collection.h"
#include "scene/scene_accel.h"
#include "backend_mesh_desc.h"
#include "test_scenes.h"

namespace obvh {
namespace {

void primsUnder(const BinaryBvh& bvh, uint32_t node, std::vector<uint32_t>& out) {
  const Bvh2Node& n = bvh.nodes[node];
  if (n.isLeaf()) {
    for (uint32_t i = 0; i < n.primCount; ++i) out.push_back(bvh.primIndices[n.firstChildOrPrim + i]);
    return;
  }
  primsUnder(bvh, n.firstChildOrPrim, out);
  primsUnder(bvh, n.firstChildOrPrim + 1, out);
}

bool contains(const Box3f& outer, const Box3f& inner) {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y && outer.lower.z <= inner.lower.z &&
         outer.upper.x >= inner.upper.x && outer.upper.y >= inner.upper.y && outer.upper.z >= inner.upper.z;
}

// Every primitive in exactly one leaf of at most maxLeafSize, every box inside its parent's.
void expectWellFormed(const BinaryBvh& bvh, const PrimRefs& input, int maxLeafSize) {
  ASSERT_FALSE(bvh.empty());
  std::vector<int> seen(input.size(), 0);
  std::vector<Box3f> boxOf(input.size());
  for (const PrimRef& r : input) boxOf[r.index] = r.bounds;
  for (uint32_t index : bvh.primIndices) ++seen[index];
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(seen.size()));
  for (const Bvh2Node& node : bvh.nodes) {
    if (node.isLeaf()) {
      EXPECT_LE(node.primCount, uint32_t(maxLeafSize));
      for (uint32_t i = 0; i < node.primCount; ++i)
        EXPECT_TRUE(contains(node.bounds, boxOf[bvh.primIndices[node.firstChildOrPrim + i]]));
    } else {
      EXPECT_TRUE(contains(node.bounds, bvh.nodes[node.firstChildOrPrim].bounds));
      EXPECT_TRUE(contains(node.bounds, bvh.nodes[node.firstChildOrPrim + 1].bounds));
    }
  }
}

PrimRefs soupRefs(size_t count, uint32_t seed) {
  const test::MeshData soup = test::randomTriangleSoup(count, seed);  // collecting copies the triangles
  return collectPrimitives({tools::backendMeshDesc(soup)}).refs;
}

TEST(KMeansBuilder, TreeIsWellFormed) {
  for (int arity : {2, 4, 8}) {
    PrimRefs refs = soupRefs(30000, 7);
    const PrimRefs input = refs;
    BuildOptions options;
    options.kmeansArity = arity;
    expectWellFormed(buildKMeans(refs, options), input, options.maxLeafSize);
  }
}

// Eight tight, well separated blobs: with k = 8 the eight nodes three binary levels below the
// root (one wide node after the collapse) are exactly the blobs.
TEST(KMeansBuilder, FindsTheClustersOfTheScene) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
  PrimRefs refs;
  std::vector<int> blobOf;
  for (int blob = 0; blob < 8; ++blob) {
    // Uneven sizes, so equal-count splitting would not find the blobs by accident.
    const int count = 200 + 150 * blob;
    const Vec3f centre{float(blob & 1) * 10.f, float((blob >> 1) & 1) * 10.f, float(blob >> 2) * 10.f};
    for (int i = 0; i < count; ++i) {
      const Vec3f c = centre + Vec3f{jitter(rng), jitter(rng), jitter(rng)};
      PrimRef r;
      r.bounds.extend(c - Vec3f{0.01f, 0.01f, 0.01f});
      r.bounds.extend(c + Vec3f{0.01f, 0.01f, 0.01f});
      r.index = uint32_t(refs.size());
      refs.push_back(r);
      blobOf.push_back(blob);
    }
  }
  BuildOptions options;
  options.kmeansArity = 8;
  const BinaryBvh bvh = buildKMeans(refs, options);
  std::vector<uint32_t> level = {0};
  for (int depth = 0; depth < 3; ++depth) {
    std::vector<uint32_t> next;
    for (uint32_t n : level) {
      ASSERT_FALSE(bvh.nodes[n].isLeaf());
      next.push_back(bvh.nodes[n].firstChildOrPrim);
      next.push_back(bvh.nodes[n].firstChildOrPrim + 1);
    }
    level = next;
  }
  std::vector<int> blobsFound;
  for (uint32_t n : level) {
    std::vector<uint32_t> prims;
    primsUnder(bvh, n, prims);
    ASSERT_FALSE(prims.empty());
    const int blob = blobOf[prims[0]];
    for (uint32_t p : prims) ASSERT_EQ(blobOf[p], blob) << "a cluster mixes two blobs";
    EXPECT_EQ(prims.size(), size_t(200 + 150 * blob));
    blobsFound.push_back(blob);
  }
  std::sort(blobsFound.begin(), blobsFound.end());
  EXPECT_EQ(std::unique(blobsFound.begin(), blobsFound.end()) - blobsFound.begin(), 8);
}

// Coincident centroids cannot be clustered: the builder still terminates with small leaves.
TEST(KMeansBuilder, IdenticalCentroidsStillSplit) {
  PrimRefs refs(1000, PrimRef{});
  for (uint32_t i = 0; i < refs.size(); ++i) {
    refs[i].bounds.extend(Vec3f{0.f, 0.f, 0.f});
    refs[i].bounds.extend(Vec3f{1.f, 1.f, 1.f});
    refs[i].index = i;
  }
  const PrimRefs input = refs;
  const BuildOptions options;
  expectWellFormed(buildKMeans(refs, options), input, options.maxLeafSize);
}

TEST(DistanceSahBuilder, TreeIsWellFormed) {
  for (float alpha : {0.f, 0.5f, 1.f}) {
    PrimRefs refs = soupRefs(30000, 9);
    const PrimRefs input = refs;
    BuildOptions options;
    options.distanceAlpha = alpha;
    options.distanceSource = {0.5f, 0.5f, 0.5f};
    expectWellFormed(buildDistanceSah(refs, options), input, options.maxLeafSize);
  }
}

// Box tests per ray for rays leaving source in every direction, through a bvh2 tree built with
// the distance-aware builder at this alpha.
double boxTestsFromSource(const SceneDesc& desc, const Vec3f& source, float alpha) {
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  BuildOptions options;
  options.layout = AccelLayout::Bvh2;  // counters are kept for the binary layout
  options.builder = TreeBuilder::Distance;
  options.distanceAlpha = alpha;
  options.distanceSource = source;
  SceneAccel accel;
  accel.build(desc, options);
  TraversalCounters counters;
  const QueryState state;
  const int rays = 20000;
  for (int i = 0; i < rays; ++i) {
    Ray ray;
    ray.org = source;
    ray.dir = {normal(rng), normal(rng), normal(rng)};
    ray.tfar = std::numeric_limits<float>::infinity();
    Hit hit;
    accel.intersect(ray, hit, state, &counters);
  }
  return double(counters.volumeTests()) / rays;
}

// What the builder is for: rays from the source need fewer box tests than through the plain SAH
// tree (alpha = 1), whose SAH cost matches the binned-SAH builder's.
TEST(DistanceSahBuilder, RaysFromTheSourceTestFewerBoxes) {
  const test::MeshData soup = test::randomTriangleSoup(40000, 13);
  SceneDesc desc;
  desc.meshes = {tools::backendMeshDesc(soup)};
  desc.geometryIdLimit = 1;
  const Vec3f source{0.1f, 0.1f, 0.1f};
  const double plain = boxTestsFromSource(desc, source, 1.f), mixed = boxTestsFromSource(desc, source, 0.5f);
  std::printf("[distance-sah] box tests per ray from the source: alpha 1 %.1f, alpha 0.5 %.1f\n", plain, mixed);
  EXPECT_LT(mixed, plain * 0.9);

  PrimRefs a = collectPrimitives(desc.meshes).refs, b = a;
  BuildOptions options;
  options.distanceSource = source;
  options.distanceAlpha = 1.f;
  const double sahDistance = measureLayout(buildDistanceSah(a, options), options).sahCost;
  const double sahBinned = measureLayout(buildBinnedSah(b, options), options).sahCost;
  EXPECT_LT(sahDistance, sahBinned * 1.05);
}

// Every layout built by the alternative builders answers like the default build: the same
// closest t and primitive on every ray (distinct random triangles: no ties).
TEST(AlternativeBuilders, EveryLayoutFindsTheSameHitsAsTheDefaultBuild) {
  const test::MeshData soup = test::randomTriangleSoup(20000, 17);
  SceneDesc desc;
  desc.meshes = {tools::backendMeshDesc(soup)};
  desc.geometryIdLimit = 1;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(-0.5f, 1.5f);
  std::vector<Ray> rays(5000);
  for (Ray& ray : rays) {
    ray.org = {unit(rng), unit(rng), unit(rng)};
    ray.dir = Vec3f{unit(rng), unit(rng), unit(rng)} - ray.org;
    ray.tfar = std::numeric_limits<float>::infinity();
  }
  const QueryState state;
  for (AccelLayout layout : {AccelLayout::Bvh2, AccelLayout::Bvh4, AccelLayout::Bvh8}) {
    BuildOptions reference;
    reference.layout = layout;
    SceneAccel expected;
    expected.build(desc, reference);
    for (TreeBuilder builder : {TreeBuilder::KMeans, TreeBuilder::Distance}) {
      BuildOptions options = reference;
      options.builder = builder;
      options.kmeansArity = layout == AccelLayout::Bvh8 ? 8 : 4;
      options.distanceSource = {0.5f, 0.5f, 0.5f};
      SceneAccel candidate;
      candidate.build(desc, options);
      size_t hits = 0;
      for (const Ray& ray : rays) {
        Ray r1 = ray, r2 = ray;
        Hit h1, h2;
        const bool found = expected.intersect(r1, h1, state);
        ASSERT_EQ(found, candidate.intersect(r2, h2, state)) << "layout " << int(layout) << " builder " << int(builder);
        ASSERT_EQ(found, expected.occluded(ray, state));
        ASSERT_EQ(found, candidate.occluded(ray, state));
        hits += found;
        if (!found) continue;
        ASSERT_EQ(r1.tfar, r2.tfar);
        ASSERT_EQ(h1.primID, h2.primID);
      }
      EXPECT_GT(hits, 1000u);
    }
  }
}

}  // namespace
}  // namespace obvh
