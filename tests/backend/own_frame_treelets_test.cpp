// The treelets rebuilt in their own frames (builders/own_frame_treelets.h): the tree stays well
// formed, the same from run to run, untouched where every triangle lies in a world-axis plane,
// and a slanted line's top face ends up in leaves apart from its bottom face, where the
// axis-aligned SAH paired a top with a bottom triangle in leaves as large as the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

#include "builders/binned_sah_builder.h"
#include "builders/own_frame_treelets.h"
#include "scene/primitive_collection.h"
#include "backend_mesh_desc.h"
#include "stack_generator.h"

namespace obvh {
namespace {

struct BuiltTree {
  CollectedPrimitives collected;
  BinaryBvh bvh;
};

BuiltTree buildAabbSah(const tools::MeshData& mesh, const BuildOptions& options) {
  BuiltTree t;
  t.collected = collectPrimitives({tools::backendMeshDesc(mesh)});
  PrimRefs refs = t.collected.refs;
  t.bvh = buildBinnedSah(refs, options);
  return t;
}

void collectLeaves(const BinaryBvh& bvh, uint32_t node, std::vector<uint32_t>& leaves, int& visits) {
  ++visits;
  const Bvh2Node& n = bvh.nodes[node];
  if (n.isLeaf()) {
    leaves.push_back(node);
    return;
  }
  collectLeaves(bvh, n.firstChildOrPrim, leaves, visits);
  collectLeaves(bvh, n.firstChildOrPrim + 1, leaves, visits);
}

// The tree as the root reaches it, leaf by leaf: the triangles of each leaf in order, -1 between
// leaves (node numbering aside, two trees with the same serialization are the same tree).
std::vector<int64_t> serialized(const BinaryBvh& bvh) {
  std::vector<uint32_t> leaves;
  int visits = 0;
  collectLeaves(bvh, 0, leaves, visits);
  std::vector<int64_t> out;
  for (uint32_t leaf : leaves) {
    const Bvh2Node& n = bvh.nodes[leaf];
    for (uint32_t i = n.firstChildOrPrim; i < n.firstChildOrPrim + n.primCount; ++i) out.push_back(bvh.primIndices[i]);
    out.push_back(-1);
  }
  return out;
}

bool contains(const Box3f& outer, const Vec3f& p) {
  return outer.lower.x <= p.x && outer.lower.y <= p.y && outer.lower.z <= p.z && outer.upper.x >= p.x &&
         outer.upper.y >= p.y && outer.upper.z >= p.z;
}

// Every triangle in exactly one leaf of at most maxLeafSize, every node reached once from the root,
// every leaf box around its triangles and every box around its children's.
void expectWellFormed(const BuiltTree& t, int maxLeafSize) {
  const BinaryBvh& bvh = t.bvh;
  ASSERT_FALSE(bvh.empty());
  std::vector<uint32_t> leaves;
  int visits = 0;
  collectLeaves(bvh, 0, leaves, visits);
  EXPECT_EQ(size_t(visits), bvh.nodes.size()) << "unreachable nodes";
  std::vector<int> seen(t.collected.triangles.size(), 0);
  for (uint32_t leaf : leaves) {
    const Bvh2Node& n = bvh.nodes[leaf];
    EXPECT_LE(n.primCount, uint32_t(maxLeafSize));
    for (uint32_t i = n.firstChildOrPrim; i < n.firstChildOrPrim + n.primCount; ++i) {
      const StoredTriangle& tri = t.collected.triangles[bvh.primIndices[i]];
      ++seen[bvh.primIndices[i]];
      for (const Vec3f& p : {tri.v0, tri.v1, tri.v2}) EXPECT_TRUE(contains(n.bounds, p));
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), long(seen.size()));
  for (const Bvh2Node& n : bvh.nodes) {
    if (n.isLeaf()) continue;
    for (uint32_t c : {n.firstChildOrPrim, n.firstChildOrPrim + 1}) {
      EXPECT_TRUE(contains(n.bounds, bvh.nodes[c].bounds.lower));
      EXPECT_TRUE(contains(n.bounds, bvh.nodes[c].bounds.upper));
    }
  }
}

BuildOptions orientedBuildOptions() {
  BuildOptions options;
  options.layout = AccelLayout::Obb;
  options.maxLeafSize = 4;
  return options;
}

TEST(OwnFrameTreelets, StackTreesStayWellFormedAndDeterministic) {
  for (const char* preset : {"small-1.5k", "vias-5.6k", "stepped-6.6k"}) {
    SCOPED_TRACE(preset);
    const tools::SceneData scene = tools::generateStack(tools::findStackPreset(preset)->params, preset).asScene();
    tools::MeshData merged;
    for (const tools::MeshData& group : scene.meshes) {
      const uint32_t base = uint32_t(merged.vertexCount());
      merged.vertices.insert(merged.vertices.end(), group.vertices.begin(), group.vertices.end());
      for (uint32_t index : group.indices) merged.indices.push_back(base + index);
    }
    const BuildOptions options = orientedBuildOptions();
    BuiltTree first = buildAabbSah(merged, options);
    BuiltTree second = buildAabbSah(merged, options);
    const std::vector<int64_t> before = serialized(first.bvh);
    rebuildTreeletsInOwnFrames(first.bvh, first.collected.triangles.data(), options);
    rebuildTreeletsInOwnFrames(second.bvh, second.collected.triangles.data(), options);
    EXPECT_NE(serialized(first.bvh), before) << "no treelet changed";
    expectWellFormed(first, options.maxLeafSize);
    ASSERT_EQ(first.bvh.nodes.size(), second.bvh.nodes.size());
    EXPECT_EQ(first.bvh.primIndices, second.bvh.primIndices);
    for (size_t i = 0; i < first.bvh.nodes.size(); ++i) {
      EXPECT_EQ(first.bvh.nodes[i].firstChildOrPrim, second.bvh.nodes[i].firstChildOrPrim);
      EXPECT_EQ(first.bvh.nodes[i].primCount, second.bvh.nodes[i].primCount);
    }
  }
}

// A closed box extruded from a footprint, as the stack generator writes its lines: eight side
// triangles, then the bottom and top fans alternately (bottom, top, bottom, top).
void addPrism(tools::MeshData& mesh, const Vec3f footprint[4], float z0, float z1) {
  const uint32_t base = uint32_t(mesh.vertexCount());
  for (float z : {z0, z1})
    for (int i = 0; i < 4; ++i) mesh.vertices.insert(mesh.vertices.end(), {footprint[i].x, footprint[i].y, z});
  for (uint32_t i = 0; i < 4; ++i) {
    const uint32_t a = base + i, b = base + (i + 1) % 4;
    mesh.indices.insert(mesh.indices.end(), {a, b, b + 4, a, b + 4, a + 4});
  }
  for (uint32_t i = 1; i < 3; ++i) {
    mesh.indices.insert(mesh.indices.end(), {base, base + i + 1, base + i});
    mesh.indices.insert(mesh.indices.end(), {base + 4, base + 4 + i, base + 4 + i + 1});
  }
}

// Lines of a layer at `degrees`, long and thin as the presets' (length 40, width 1, height 1).
tools::MeshData slantedLines(float degrees, int count) {
  const float a = degrees * 3.14159265f / 180.f;
  const Vec3f along{std::cos(a), std::sin(a), 0.f}, across{-std::sin(a), std::cos(a), 0.f};
  tools::MeshData mesh;
  for (int line = 0; line < count; ++line) {
    const Vec3f start = across * (2.f * float(line));
    const Vec3f footprint[4] = {start, start + along * 40.f, start + along * 40.f + across, start + across};
    addPrism(mesh, footprint, 0.f, 1.f);
  }
  return mesh;
}

// Triangle roles within a prism of slantedLines: 8 sides, then bottom, top, bottom, top.
enum class Face { Side, Bottom, Top };
Face faceOf(uint32_t primID) {
  const uint32_t k = primID % 12;
  return k < 8 ? Face::Side : (k % 2 == 0 ? Face::Bottom : Face::Top);
}

// How many leaves hold both a top and a bottom triangle: a ray down onto the line's top face
// enters each such leaf's box, which spans the whole line.
int leavesMixingTopAndBottom(const BuiltTree& t) {
  std::vector<uint32_t> leaves;
  int visits = 0;
  collectLeaves(t.bvh, 0, leaves, visits);
  int mixed = 0;
  for (uint32_t leaf : leaves) {
    const Bvh2Node& n = t.bvh.nodes[leaf];
    std::set<Face> faces;
    for (uint32_t i = n.firstChildOrPrim; i < n.firstChildOrPrim + n.primCount; ++i)
      faces.insert(faceOf(t.collected.triangles[t.bvh.primIndices[i]].primID));
    mixed += faces.count(Face::Top) && faces.count(Face::Bottom);

  }
  return mixed;
}

// Treelets regroup only within themselves, so a split the axis-aligned SAH made above them stays
// (at 60 degrees 4 of 12 such leaves remain); over the three angles, at most a third remain.
TEST(OwnFrameTreelets, SlantedLinesKeepTopAndBottomFacesApart) {
  int mixedBefore = 0, mixedAfter = 0;
  for (float degrees : {30.f, 45.f, 60.f}) {
    SCOPED_TRACE(degrees);
    const BuildOptions options = orientedBuildOptions();
    BuiltTree t = buildAabbSah(slantedLines(degrees, 6), options);
    const int before = leavesMixingTopAndBottom(t);
    rebuildTreeletsInOwnFrames(t.bvh, t.collected.triangles.data(), options);
    expectWellFormed(t, options.maxLeafSize);
    const int after = leavesMixingTopAndBottom(t);
    EXPECT_LE(after, before);
    mixedBefore += before;
    mixedAfter += after;
  }
  EXPECT_GT(mixedBefore, 0) << "the axis-aligned SAH no longer mixes the faces: the test shows nothing";
  EXPECT_LE(3 * mixedAfter, mixedBefore);
}

TEST(OwnFrameTreelets, AxisAlignedTreeletsStayAsBuilt) {
  const BuildOptions options = orientedBuildOptions();
  BuiltTree t = buildAabbSah(slantedLines(0.f, 6), options);
  const std::vector<int64_t> before = serialized(t.bvh);
  const size_t nodesBefore = t.bvh.nodes.size();
  rebuildTreeletsInOwnFrames(t.bvh, t.collected.triangles.data(), options);
  EXPECT_EQ(t.bvh.nodes.size(), nodesBefore);
  EXPECT_EQ(serialized(t.bvh), before);
}

}  // namespace
}  // namespace obvh
