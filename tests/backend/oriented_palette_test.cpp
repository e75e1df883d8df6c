// The frame palette (obb_palette): the tree it builds, and its eight-wide kernel against the
// per-child transform on the very same tree, which must enter the same children and answer alike.
#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "builders/binned_sah_builder.h"
#include "bvh/oriented_layout.h"
#include "bvh/oriented_wide_bvh.h"
#include "obb/obb.h"
#include "scene/primitive_collection.h"
#include "simd/cpu_features.h"
#include "traversal/oriented_wide_traversal.h"
#include "backend_mesh_desc.h"
#include "stack_generator.h"

namespace obvh {
namespace {

struct PaletteTree {
  StoredTriangles inLeafOrder;
  OrientedBvh binary;
  OrientedWideBvh<8> wide;
};

// mixed-6.9k: lines at several angles, vias and steps, more directions than a small palette holds.
PaletteTree buildMixedStack(int paletteFrames) {
  const tools::SceneData scene = tools::generateStack(tools::findStackPreset("mixed-6.9k")->params, "mixed").asScene();
  CollectedPrimitives collected = collectPrimitives(tools::backendSceneDesc(scene).meshes);
  BuildOptions options;
  options.layout = AccelLayout::Obb;
  options.obbPalette = paletteFrames;
  const BinaryBvh tree = buildBinnedSah(collected.refs, options);
  PaletteTree out;
  for (uint32_t prim : tree.primIndices) out.inLeafOrder.push_back(collected.triangles[prim]);
  out.binary = makeOrientedLayout(tree, out.inLeafOrder.data(), options);
  out.wide = collapseOrientedToWide<8>(out.binary, out.inLeafOrder.data());
  return out;
}

Obb boxOf(const PaletteTree& t, const OrientedNode& node) {
  Obb box;
  if (node.oriented())
    for (int k = 0; k < 3; ++k) box.axis[k] = t.binary.frames[node.frame].axis[k];
  box.lower = node.lower, box.upper = node.upper;
  return box;
}

void expectTrianglesInside(const PaletteTree& t, uint32_t index, std::vector<Obb> ancestors) {
  const OrientedNode& node = t.binary.nodes[index];
  ancestors.push_back(boxOf(t, node));
  if (!node.isLeaf()) {
    expectTrianglesInside(t, node.firstChildOrPrim, ancestors);
    expectTrianglesInside(t, node.firstChildOrPrim + 1, ancestors);
    return;
  }
  for (uint32_t p = node.firstChildOrPrim; p < node.firstChildOrPrim + node.primCount; ++p)
    for (const Vec3f& v : {t.inLeafOrder[p].v0, t.inLeafOrder[p].v1, t.inLeafOrder[p].v2})
      for (const Obb& box : ancestors) ASSERT_TRUE(box.contains(v, 1e-5f)) << "node " << index;
}

TEST(FramePalette, OrientedNodesShareAtMostThePalettesFrames) {
  const PaletteTree t = buildMixedStack(3);
  ASSERT_GT(t.binary.paletteFrames, 0u);
  ASSERT_LE(t.binary.paletteFrames, 3u);
  size_t inPalette = 0, ownFrame = 0;
  for (const OrientedNode& node : t.binary.nodes) {
    if (!node.oriented()) continue;
    ASSERT_LT(node.frame, t.binary.frames.size());
    (node.frame < t.binary.paletteFrames ? inPalette : ownFrame) += 1;
  }
  // Most oriented boxes take a palette frame; walls no palette frame fits keep their own.
  EXPECT_GT(inPalette, 10 * ownFrame);
  EXPECT_GT(ownFrame, 0u);
  // Every triangle lies in the box of each node above it (interior boxes in palette frames are
  // unions of their children's).
  const std::vector<Obb> noAncestors;
  expectTrianglesInside(t, 0, noAncestors);
  size_t paletteNodes = 0;
  for (const OrientedWideNode<8>& node : t.wide.nodes) paletteNodes += node.inPalette != 0;
  EXPECT_TRUE(t.wide.hasPalette);
  EXPECT_GT(paletteNodes, 0u);
  EXPECT_LT(paletteNodes, t.wide.nodes.size());  // both kinds of node are traced below
}

TEST(FramePalette, KernelEntersTheSameChildrenAsThePerChildTransform) {
  if (!simd::cpuHasAvx2()) GTEST_SKIP() << "the palette kernel is the eight-wide one, which needs AVX2";
  const PaletteTree t = buildMixedStack(3);
  OrientedWideBvh<8> perChild = t.wide;
  perChild.hasPalette = false;
  const uint32_t allMasks[16] = {~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};
  const uint8_t noFilters[16] = {};
  TriangleSet set;
  set.triangles = t.inLeafOrder.data();
  set.geometryMasks = allMasks;
  set.intersectFiltered = noFilters;
  set.occlusionFiltered = noFilters;
  const TriangleOrientedWideView<8> palette = makeOrientedWideView(t.wide, set),
                                    transformed = makeOrientedWideView(perChild, set);
  Box3f bounds;
  for (const StoredTriangle& tri : t.inLeafOrder) bounds.extend(tri.v0), bounds.extend(tri.v1), bounds.extend(tri.v2);
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  auto inBox = [&](float grow) {
    const Vec3f e = bounds.upper - bounds.lower;
    return Vec3f{bounds.lower.x + e.x * (unit(rng) * (1 + 2 * grow) - grow),
                 bounds.lower.y + e.y * (unit(rng) * (1 + 2 * grow) - grow),
                 bounds.lower.z + e.z * (unit(rng) * (1 + 2 * grow) - grow)};
  };
  const QueryState state;
  size_t hits = 0;
  for (int i = 0; i < 30000; ++i) {
    Ray ray;
    ray.org = inBox(0.3f);
    ray.dir = i % 3 == 0 ? Vec3f{0.f, 0.f, -1.f} : inBox(0.f) - ray.org;  // a third along an axis, as orthographic views
    if (i % 3 == 0) ray.org.z = bounds.upper.z + 1.f;
    ray.tfar = std::numeric_limits<float>::infinity();
    Ray r1 = ray, r2 = ray;
    Hit h1, h2;
    TraversalCounters c1, c2;
    const bool f1 = intersectClosestOrientedWide(palette, r1, h1, state, &c1);
    ASSERT_EQ(f1, intersectClosestOrientedWide(transformed, r2, h2, state, &c2)) << "ray " << i;
    ASSERT_EQ(c1.obbTests, c2.obbTests) << "ray " << i;
    ASSERT_EQ(c1.leafVisits, c2.leafVisits) << "ray " << i;
    ASSERT_EQ(intersectAnyOrientedWide(palette, ray, state), intersectAnyOrientedWide(transformed, ray, state)) << "ray " << i;
    hits += f1;
    if (!f1) continue;
    ASSERT_EQ(r1.tfar, r2.tfar) << "ray " << i;
    ASSERT_EQ(h1.primID, h2.primID) << "ray " << i;
    ASSERT_EQ(h1.u, h2.u) << "ray " << i;
    ASSERT_EQ(h1.v, h2.v) << "ray " << i;
  }
  EXPECT_GT(hits, 10000u);
}

}  // namespace
}  // namespace obvh
