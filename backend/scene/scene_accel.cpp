#include "scene/scene_accel.h"
#include "scene/shape_controls.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include "builders/binned_sah_builder.h"
#include "builders/distance_sah_builder.h"
#include "builders/kmeans_builder.h"
#include "builders/morton_builder.h"
#include "builders/obb_split_builder.h"
#include "builders/own_frame_treelets.h"
#include "builders/spatial_split_builder.h"
#include "bvh/tree_statistics.h"
#include "bvh/oriented_layout.h"
#include "memory/huge_pages.h"
#include "scene/primitive_collection.h"
#include "simd/cpu_features.h"
#include "traversal/bvh2_traverse.h"

namespace obvh {
namespace {

bool isUsableBox(const Box3f& b) {
  const float c[6] = {b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z};
  for (float v : c)
    if (!std::isfinite(v)) return false;
  return !b.empty();
}

float distanceSquaredToBox(const Vec3f& p, const Box3f& b) {
  float d = 0.f;
  for (int axis = 0; axis < 3; ++axis) {
    const float e = std::max(std::max(b.lower[axis] - p[axis], 0.f), p[axis] - b.upper[axis]);
    d += e * e;
  }
  return d;
}

// Stack traversal of a BVH with a sphere whose radius may shrink while it runs.
template <typename Radius, typename LeafVisitor>
void traverseSphere(const BinaryBvh& bvh, const Vec3f& p, Radius&& radius, LeafVisitor&& visit) {
  if (bvh.empty()) return;
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Bvh2Node& node = bvh.nodes[stack[--top]];
    const float r = radius();
    if (!(distanceSquaredToBox(p, node.bounds) <= r * r)) continue;
    if (node.isLeaf()) {
      visit(node);
      continue;
    }
    if (top + 2 <= 128) {
      stack[top++] = node.firstChildOrPrim + 1;
      stack[top++] = node.firstChildOrPrim;
    }
  }
}

// The wide tree's counterpart: visit(block) for every leaf block under a child box that overlaps the
// sphere (the callers test each triangle's own box).
template <int N, typename Radius, typename BlockVisitor>
void traverseSphere(const WideBvh<N>& bvh, const Vec3f& p, Radius&& radius, BlockVisitor&& visit) {
  using Node = WideNode<N>;
  if (bvh.empty()) return;
  const auto visitLeaf = [&](uint32_t code) {
    const uint32_t first = Node::leafFirstBlock(code);
    for (uint32_t b = first; b < first + Node::leafBlockCount(code); ++b) visit(bvh.blocks[b]);
  };
  if (Node::isLeaf(bvh.rootChild)) return visitLeaf(bvh.rootChild);
  std::vector<uint32_t> stack{bvh.rootChild};
  while (!stack.empty()) {
    const Node& node = bvh.nodes[stack.back()];
    stack.pop_back();
    for (int lane = 0; lane < N; ++lane) {
      const uint32_t child = node.child[lane];
      const float r = radius();
      if (child == Node::kEmptyChild || !(distanceSquaredToBox(p, node.childBox(lane)) <= r * r)) continue;
      if (Node::isLeaf(child))
        visitLeaf(child);
      else
        stack.push_back(child);
    }
  }
}

}  // namespace

// The triangle tree of the chosen layout (and, for the oriented layouts, its oriented boxes). The
// builders reorder collected.refs.
void SceneAccel::buildTriangleTree(CollectedPrimitives& collected, const BuildOptions& options) {
  layout_ = options.layout;
  // The hybrid may settle on the wide AABB layout and build again: from the refs as collected.
  PrimRefs collectedRefs;
  if (layout_ == AccelLayout::Hybrid) collectedRefs = collected.refs;
  BuildOptions triangleOptions = options;
  const bool wide = layout_ == AccelLayout::Bvh4 || layout_ == AccelLayout::Bvh8;
  const bool oriented = layout_ == AccelLayout::Obb || layout_ == AccelLayout::Hybrid;
  const bool sahDecidesLeaves = options.builder == TreeBuilder::Distance ||
                                (options.builder == TreeBuilder::Sah && options.quality != BuildQuality::Low);
  if (options.maxLeafSize <= 0) triangleOptions.maxLeafSize = defaultMaxLeafSize(layout_, sahDecidesLeaves);
  if (wide || (oriented && options.obbWidth > 2)) {
    // A wide leaf's block count has 4 bits.
    triangleOptions.maxLeafSize = std::min<int>(triangleOptions.maxLeafSize, 4 * Bvh4Node::kMaxLeafBlocks);
  }
  if (wide) {
    triangleOptions.leafBlockSize = 4;
    // The builders weigh leaf against split on the binary tree, whose interior nodes the collapse
    // merges: one wide node stands for about log2(width) binary levels, so a binary node costs
    // that fraction of a node visit. (At full cost, leaves larger than four were chosen where
    // splitting was cheaper in the wide tree: bunny SAH 10.85 -> 11.68 with 28-triangle leaves.)
    triangleOptions.traversalCost = options.traversalCost / std::log2(float(layout_ == AccelLayout::Bvh8 ? 8 : 4));
  }
  options_ = triangleOptions;
  if (oriented && options.obbSplit != ObbSplit::AabbSah) {
    triangleBvh_ = buildInObbFrames(collected.refs, collected.triangles.data(), triangleOptions);
  } else if (!oriented && options.builder == TreeBuilder::KMeans) {
    triangleBvh_ = buildKMeans(collected.refs, triangleOptions);
  } else if (!oriented && options.builder == TreeBuilder::Distance) {
    triangleBvh_ = buildDistanceSah(collected.refs, triangleOptions);
  } else if (!oriented && options.quality == BuildQuality::High) {
    SpatialSplitSettings settings;
    settings.referenceBudget = options.spatialBudget;
    triangleBvh_ = buildSpatialSah(collected.refs, collected.triangles.data(), triangleOptions, settings);
  } else if (!oriented && options.quality == BuildQuality::Low) {
    triangleBvh_ = buildMorton(collected.refs, triangleOptions);
  } else {
    triangleBvh_ = buildBinnedSah(collected.refs, triangleOptions);
  }
  if (oriented && options.obbSplit == ObbSplit::AabbSah)
    rebuildTreeletsInOwnFrames(triangleBvh_, collected.triangles.data(), triangleOptions);
  // The wide layouts that keep no binary tree (BuildOptions::keepBinaryTree) keep no copy of the
  // triangles either: their collapse reads them where they were collected, through primIndices.
  triangles_ = StoredTriangles{};
  if (!wide || options.keepBinaryTree) {
    reserveWithHugePages(triangles_, triangleBvh_.primIndices.size());
    triangles_.resize(triangleBvh_.primIndices.size());
    tbb::parallel_for(size_t(0), triangles_.size(),
                      [&](size_t i) { triangles_[i] = collected.triangles[triangleBvh_.primIndices[i]]; });
  }
  triangleOriented_ = OrientedBvh{};
  if (triangleBvh_.empty() || !oriented) return;
  triangleOriented_ = makeOrientedLayout(triangleBvh_, triangles_.data(), triangleOptions);
  if (layout_ == AccelLayout::Hybrid && !orientedBoxesPayOff()) {
    // Settle on the wide AABB layout, built as that layout builds itself (its SAH chooses leaves
    // up to 28 triangles): kept from the hybrid's own build, whose leaves hold four, it traced
    // 1.4x slower than accel=bvh8 on the small presets.
    BuildOptions wide = options;
    wide.layout = simd::cpuHasAvx2() ? AccelLayout::Bvh8 : AccelLayout::Bvh4;
    collected.refs = std::move(collectedRefs);
    buildTriangleTree(collected, wide);
  }
}

void SceneAccel::build(const SceneDesc& desc, const BuildOptions& options) {
  owner_ = desc.owner;
  geometryMasks_.assign(desc.geometryIdLimit, 0u);
  for (const MeshDesc& mesh : desc.meshes) geometryMasks_[mesh.geomID] = mesh.mask;
  for (const InstanceDesc& inst : desc.instances) geometryMasks_[inst.geomID] = inst.mask;
  for (const UserGeometryDesc& user : desc.userGeometries) geometryMasks_[user.geomID] = user.mask;
  for (const ShapeGeometryDesc& shape : desc.shapes) geometryMasks_[shape.geomID] = shape.mask;
  intersectFiltered_ = desc.intersectFiltered;
  occlusionFiltered_ = desc.occlusionFiltered;
  intersectFiltered_.resize(desc.geometryIdLimit, 0);
  occlusionFiltered_.resize(desc.geometryIdLimit, 0);

  requested_ = options;
  std::vector<MeshDesc> still, moving;
  for (const MeshDesc& mesh : desc.meshes) (mesh.moving() ? moving : still).push_back(mesh);
  CollectedPrimitives collected = collectPrimitives(still);
  gridCells_ = std::move(collected.gridCells);
  subdivCells_ = std::move(collected.subdivCells);
  motion_ = collectMotionPrimitives(moving);
  buildTriangleTree(collected, options);

  std::vector<ObjectRef> objects;
  PrimRefs objectRefs;
  instances_.clear();
  for (const InstanceDesc& inst : desc.instances) {
    if (!inst.child) continue;
    const Box3f world = inst.motion.moving() ? inst.motion.bounds(inst.child->bounds())
                                             : inst.localToWorld.xfmBounds(inst.child->bounds());
    if (!isUsableBox(world)) continue;
    objectRefs.push_back({world, uint32_t(objects.size())});
    objects.push_back({ObjectKind::Instance, uint32_t(instances_.size()), 0, world});
    instances_.push_back(makeInstance(inst.child, inst.localToWorld, inst.geomID));
    instances_.back().motion = inst.motion;
  }
  for (const UserGeometryDesc& user : desc.userGeometries)
    for (size_t prim = 0; prim < user.primitiveBounds.size(); ++prim) {
      if (!isUsableBox(user.primitiveBounds[prim])) continue;
      objectRefs.push_back({user.primitiveBounds[prim], uint32_t(objects.size())});
      objects.push_back({ObjectKind::UserPrimitive, user.geomID, uint32_t(prim), user.primitiveBounds[prim]});
    }
  for (size_t i = 0; i < motion_.triangles.size(); ++i) {
    const Box3f bounds = motion_.triangles[i].bounds(motion_.vertices);
    objectRefs.push_back({bounds, uint32_t(objects.size())});
    objects.push_back({ObjectKind::MotionTriangle, uint32_t(i), motion_.triangles[i].primID, bounds});
  }
  shapes_.clear();
  shapeSteps_.clear();
  for (const ShapeGeometryDesc& geometry : desc.shapes) {
    const int count = controlPointCount(geometry.kind);
    const bool curve = geometry.kind != ShapeKind::Sphere;
    const size_t primitives = curve ? geometry.segments.size() : geometry.vertices.size();
    const size_t steps = 1 + geometry.laterSteps.size();
    const auto stepVertices = [&](size_t step) -> const std::vector<ShapeVertex>& {
      return step == 0 ? geometry.vertices : geometry.laterSteps[step - 1];
    };
    for (size_t prim = 0; prim < primitives; ++prim) {
      ShapePrimitive shape{geometry.kind, geometry.geomID, uint32_t(prim), geometry.ribbonQuads, {}};
      const size_t first = curve ? geometry.segments[prim] : prim;
      if (first + size_t(count) > geometry.vertices.size()) continue;
      Box3f bounds;
      for (size_t step = 0; step < steps; ++step) {
        const ShapeControls controls = shapeControls(geometry.kind, &stepVertices(step)[first]);
        bounds.extend(controls.bounds);
        if (step == 0) std::copy(controls.v, controls.v + count, shape.v);
        if (steps > 1) shapeSteps_.insert(shapeSteps_.end(), controls.v, controls.v + count);
      }
      if (steps > 1) {
        shape.firstStep = uint32_t(shapeSteps_.size() - size_t(count) * steps);
        shape.stepCount = uint32_t(steps);
        shape.timeStart = geometry.timeStart, shape.timeEnd = geometry.timeEnd;
      }
      if (!isUsableBox(bounds)) continue;
      objectRefs.push_back({bounds, uint32_t(objects.size())});
      objects.push_back({ObjectKind::Shape, uint32_t(shapes_.size()), uint32_t(prim), bounds});
      shapes_.push_back(shape);
    }
  }
  BuildOptions objectOptions = options;
  if (objectOptions.maxLeafSize <= 0) objectOptions.maxLeafSize = defaultMaxLeafSize(AccelLayout::Bvh2, true);
  objectBvh_ = buildBinnedSah(objectRefs, objectOptions);
  objects_.resize(objectBvh_.primIndices.size());
  for (size_t i = 0; i < objects_.size(); ++i) objects_[i] = objects[objectBvh_.primIndices[i]];

  bounds_ = Box3f{};
  if (!triangleBvh_.empty()) bounds_.extend(triangleBvh_.nodes[0].bounds);
  if (!objectBvh_.empty()) bounds_.extend(objectBvh_.nodes[0].bounds);
  makeTriangleViews(triangles_.size() == triangleBvh_.primIndices.size()
                        ? TrianglesInLeafOrder(triangles_.data())
                        : TrianglesInLeafOrder(collected.triangles.data(), triangleBvh_.primIndices.data()));
}

// The traced forms of the binary tree: its wide collapse when that layout is selected, and the
// views the queries use. trianglesInLeafOrder: the binary tree's triangles (triangles_, unless a
// wide layout keeps none).
void SceneAccel::makeTriangleViews(TrianglesInLeafOrder trianglesInLeafOrder) {
  const TriangleSet set{triangles_.data(),      geometryMasks_.data(),
                        intersectFiltered_.data(), occlusionFiltered_.data(),
                        owner_,                 options_.intersector == IntersectorMode::Fast,
                        gridCells_.data(),      subdivCells_.data()};
  motionSet_ = set;
  motionSet_.triangles = nullptr;
  motionSet_.gridCells = motion_.gridCells.data();
  motionSet_.subdivCells = motion_.subdivCells.data();
  triangleView_ = TriangleBvhView{};
  triangleView4_ = {};
  triangleBvh4_ = {};
  triangleView8_ = {};
  triangleBvh8_ = {};
  triangleOrientedView_ = TriangleOrientedView{};
  triangleOrientedWide4_ = {};
  triangleOrientedWideView4_ = {};
  triangleOrientedWide8_ = {};
  triangleOrientedWideView8_ = {};
  triangleCount_ = triangleBvh_.primIndices.size();
  triangleLeafCount_ = 0;
  for (const Bvh2Node& node : triangleBvh_.nodes) triangleLeafCount_ += node.isLeaf() ? 1 : 0;
  triangleBounds_ = triangleBvh_.empty() ? Box3f{} : triangleBvh_.nodes[0].bounds;
  if (triangleBvh_.empty()) return;
  triangleView_ = {triangleBvh_.nodes.data(), set};
  if (!triangleOriented_.nodes.empty()) {
    triangleOrientedView_ = {&triangleOriented_, set};
    OrientedCollapseOptions collapse;
    collapse.sahOptimal = options_.collapse == WideCollapse::SahOptimal;
    // Merging subtrees into leaves beyond the binary tree's leaf size (28 like bvh8's), or costing a
    // node visit 1.5-2 block tests, traced within noise of these settings on the small presets.
    collapse.maxLeafPrims = uint32_t(std::max(options_.maxLeafSize, 1));
    if (options_.obbWidth == 4) {
      triangleOrientedWide4_ = collapseOrientedToWide<4>(triangleOriented_, triangles_.data(), collapse);
      triangleOrientedWideView4_ = makeOrientedWideView(triangleOrientedWide4_, set);
    } else if (options_.obbWidth == 8) {
      triangleOrientedWide8_ = collapseOrientedToWide<8>(triangleOriented_, triangles_.data(), collapse);
      triangleOrientedWideView8_ = makeOrientedWideView(triangleOrientedWide8_, set);
    }
  }
  CollapseOptions collapse;
  // The SAH-optimal collapse is the default: it costs no build time and traced faster on the
  // meshes and stacks, except the stacks' shadow rays (README, Performance).
  collapse.method = options_.collapse == WideCollapse::Greedy ? CollapseMethod::Greedy : CollapseMethod::SahOptimal;
  collapse.maxLeafPrims = uint32_t(std::max(options_.maxLeafSize, 1));
  if (layout_ == AccelLayout::Bvh4) {
    triangleBvh4_ = collapseToWide<4>(triangleBvh_, trianglesInLeafOrder, collapse);
    triangleView4_ = makeWideView(triangleBvh4_, set, options_.childOrder);
  } else if (layout_ == AccelLayout::Bvh8) {
    triangleBvh8_ = collapseToWide<8>(triangleBvh_, trianglesInLeafOrder, collapse);
    triangleView8_ = makeWideView(triangleBvh8_, set, options_.childOrder);
  }
  if ((layout_ == AccelLayout::Bvh4 || layout_ == AccelLayout::Bvh8) && !options_.keepBinaryTree) releaseBinaryTree();
}

// The wide layouts' kernels read only the wide nodes and blocks (a block holds its triangles'
// vertices and ids), and point queries walk the wide tree instead. What the scene holds (verbose=2)
// fell from 8.49 to 4.18 MB on the bunny, from 111.2 to 56.2 MB on the dragon.
void SceneAccel::releaseBinaryTree() {
  triangleBvh_ = BinaryBvh{};
  triangleView_ = TriangleBvhView{};
}

// The hybrid's whole-tree choice. Both layouts trace wide nodes, but an oriented child costs a
// transform of the ray into its frame: per unit of the binary trees' SAH cost the eight-wide AABB
// layout traced 1.5-2.1x faster than the eight-wide oriented one (SAH collapse) on the five stack
// presets up to 42k triangles, 2.5-3.5x faster than the four-wide greedy one (README, layout
// study). The hybrid keeps the oriented tree where it cuts the SAH cost at least
// kWideAabbAdvantage-fold: the slanted presets cut it 4-17-fold, the axis-aligned preset and the
// real meshes not at all (0.7-0.9), so any factor from 1 to 4 makes the same choices there; 3
// leaves the doubtful cases to the AABB layout. (Against the binary oriented tree, obb_width=2,
// the wide AABB layout was 5.6-7.4x faster a unit.)
bool SceneAccel::orientedBoxesPayOff() const {
  const double kWideAabbAdvantage = options_.obbWidth > 2 ? 3.0 : 6.5;
  if (options_.maxLeafSize > int(4 * Bvh4Node::kMaxLeafBlocks)) return true;  // no wide layout can hold the leaves
  return measureLayout(triangleOriented_, options_).sahCost * kWideAabbAdvantage <
         measureLayout(triangleBvh_, options_).sahCost;
}

namespace {

// Post-order: every node's box becomes the union of its triangles' or children's boxes.
Box3f refitNode(BinaryBvh& bvh, uint32_t index, const StoredTriangles& triangles) {
  const Bvh2Node node = bvh.nodes[index];
  Box3f box;
  if (node.isLeaf()) {
    for (uint32_t i = node.firstChildOrPrim; i < node.firstChildOrPrim + node.primCount; ++i) {
      box.extend(triangles[i].v0);
      box.extend(triangles[i].v1);
      box.extend(triangles[i].v2);
    }
  } else {
    box = refitNode(bvh, node.firstChildOrPrim, triangles);
    box.extend(refitNode(bvh, node.firstChildOrPrim + 1, triangles));
  }
  bvh.nodes[index].bounds = box;
  return box;
}

bool sameOptions(const BuildOptions& a, const BuildOptions& b) {
  return a.layout == b.layout && a.intersector == b.intersector && a.childOrder == b.childOrder &&
         a.binCount == b.binCount &&
         a.maxLeafSize == b.maxLeafSize && a.obbSplit == b.obbSplit && a.obbClusters == b.obbClusters && a.obbPalette == b.obbPalette &&
         a.obbWidth == b.obbWidth && a.obbPackets == b.obbPackets &&
         a.quality == b.quality && a.spatialBudget == b.spatialBudget && a.collapse == b.collapse &&
         a.traversalCost == b.traversalCost &&
         a.intersectionCost == b.intersectionCost && a.builder == b.builder && a.kmeansArity == b.kmeansArity &&
         a.distanceAlpha == b.distanceAlpha && a.distanceSource.x == b.distanceSource.x &&
         a.distanceSource.y == b.distanceSource.y && a.distanceSource.z == b.distanceSource.z;
}

}  // namespace

bool SceneAccel::refit(const SceneDesc& desc, const BuildOptions& options) {
  if (triangleBvh_.empty() || !sameOptions(options, requested_)) return false;
  if (layout_ == AccelLayout::Obb || layout_ == AccelLayout::Hybrid) return false;
  if (!desc.instances.empty() || !desc.userGeometries.empty() || !desc.shapes.empty() || !objects_.empty()) return false;
  if (desc.geometryIdLimit != geometryMasks_.size()) return false;
  if (!motion_.triangles.empty()) return false;
  for (const MeshDesc& mesh : desc.meshes)
    if (mesh.moving()) return false;
  std::vector<uint8_t> intersectFiltered = desc.intersectFiltered, occlusionFiltered = desc.occlusionFiltered;
  intersectFiltered.resize(desc.geometryIdLimit, 0);
  occlusionFiltered.resize(desc.geometryIdLimit, 0);
  if (intersectFiltered != intersectFiltered_ || occlusionFiltered != occlusionFiltered_) return false;
  for (const MeshDesc& mesh : desc.meshes)
    if (geometryMasks_[mesh.geomID] != mesh.mask) return false;
  const CollectedPrimitives collected = collectPrimitives(desc.meshes);
  // The same primitives must be valid as before (a vertex turning NaN drops its primitive).
  if (collected.triangles.size() != triangles_.size()) return false;
  const std::vector<uint32_t>& order = triangleBvh_.primIndices;
  for (size_t i = 0; i < triangles_.size(); ++i) {
    const StoredTriangle& now = collected.triangles[order[i]];
    if (now.geomID != triangles_[i].geomID || now.primID != triangles_[i].primID || now.kind != triangles_[i].kind)
      return false;
  }
  owner_ = desc.owner;
  gridCells_ = collected.gridCells;
  subdivCells_ = collected.subdivCells;
  tbb::parallel_for(size_t(0), triangles_.size(), [&](size_t i) { triangles_[i] = collected.triangles[order[i]]; });
  refitNode(triangleBvh_, 0, triangles_);
  bounds_ = triangleBvh_.nodes[0].bounds;
  makeTriangleViews(triangles_.data());
  return true;
}

std::pair<Box3f, Box3f> SceneAccel::linearBounds() const {
  Box3f still;
  if (triangleCount_ > 0) still.extend(triangleBounds_);
  for (const ObjectRef& object : objects_)
    if (object.kind != ObjectKind::MotionTriangle) still.extend(object.bounds);
  Box3f start = still, end = still;
  for (const MotionTriangle& motion : motion_.triangles) {
    const auto stepBox = [&](uint32_t step) {
      Box3f box;
      for (int k = 0; k < 3; ++k) box.extend(motion_.vertices[motion.firstVertex + 3 * size_t(step) + k]);
      return box;
    };
    if (motion.timeStart != 0.f || motion.timeEnd != 1.f) {  // steps off the shutter's ends: all of it
      start.extend(motion.bounds(motion_.vertices));
      end.extend(motion.bounds(motion_.vertices));
      continue;
    }
    // The first and last steps' boxes, widened until the blend holds every step in between.
    const uint32_t last = motion.stepCount - 1;
    Box3f b0 = stepBox(0), b1 = stepBox(last);
    for (uint32_t step = 1; step < last; ++step) {
      const Box3f b = stepBox(step);
      const float t = float(step) / float(last);
      for (int a = 0; a < 3; ++a) {
        const float below = (1.f - t) * b0.lower[a] + t * b1.lower[a] - b.lower[a];
        if (below > 0.f) b0.lower[a] -= below, b1.lower[a] -= below;
        const float above = b.upper[a] - ((1.f - t) * b0.upper[a] + t * b1.upper[a]);
        if (above > 0.f) b0.upper[a] += above, b1.upper[a] += above;
      }
    }
    start.extend(b0);
    end.extend(b1);
  }
  return {start, end};
}

bool SceneAccel::intersectOrientedWideTriangles(Ray& ray, Hit& hit, const QueryState& state,
                                                TraversalCounters* counters) const {
  if (!triangleOrientedWideView8_.empty())
    return intersectClosestOrientedWide(triangleOrientedWideView8_, ray, hit, state, counters);
  return !triangleOrientedWideView4_.empty() &&
         intersectClosestOrientedWide(triangleOrientedWideView4_, ray, hit, state, counters);
}

bool SceneAccel::occludedOrientedWideTriangles(const Ray& ray, const QueryState& state,
                                               TraversalCounters* counters) const {
  if (!triangleOrientedWideView8_.empty())
    return intersectAnyOrientedWide(triangleOrientedWideView8_, ray, state, counters);
  return !triangleOrientedWideView4_.empty() && intersectAnyOrientedWide(triangleOrientedWideView4_, ray, state, counters);
}

QueryEntry SceneAccel::queryEntry() const {
  if (layout_ == AccelLayout::Bvh8) return obvh::queryEntry(triangleView8_);
  if (layout_ == AccelLayout::Bvh4) return obvh::queryEntry(triangleView4_);
  // The oriented layouts choose their kernels inside (intersectClosestOrientedWide, intersectPacket).
  QueryEntry entry;
  entry.target = this;
  auto closest = [](const void* accel, Ray& ray, Hit& hit, const QueryState& state) {
    return static_cast<const SceneAccel*>(accel)->intersectOrientedWideTriangles(ray, hit, state, nullptr);
  };
  auto any = [](const void* accel, const Ray& ray, const QueryState& state) {
    return static_cast<const SceneAccel*>(accel)->occludedOrientedWideTriangles(ray, state, nullptr);
  };
  entry.closest[0] = entry.closest[1] = closest;
  entry.any[0] = entry.any[1] = any;
  entry.closestPacket = [](const void* accel, Ray* rays, Hit* hits, uint32_t active, const QueryState& state) {
    return static_cast<const SceneAccel*>(accel)->intersectPacket(rays, hits, active, state);
  };
  entry.anyPacket = [](const void* accel, const Ray* rays, uint32_t active, const QueryState& state) {
    return static_cast<const SceneAccel*>(accel)->occludedPacket(rays, active, state);
  };
  return entry;
}

bool SceneAccel::intersect(Ray& ray, Hit& hit, const QueryState& state, TraversalCounters* counters) const {
  // An explicit counters argument (the layout study) counts like state.counters (heatmaps); the
  // normal query path has neither and copies nothing.
  if (counters && counters != state.counters) {
    QueryState counted = state;
    counted.counters = counters;
    return intersect(ray, hit, counted);
  }
  counters = state.counters;
  bool found = false;
  if (layout_ == AccelLayout::Bvh4 || layout_ == AccelLayout::Bvh8)
    found = intersectWideTriangles(ray, hit, state);
  else if (layout_ == AccelLayout::Bvh2)
    found = !triangleView_.empty() && intersectClosest(triangleView_, ray, hit, state, counters);
  else if (orientedWide())
    found = intersectOrientedWideTriangles(ray, hit, state, counters);
  else
    found = !triangleOrientedView_.empty() && intersectClosestOriented(triangleOrientedView_, ray, hit, state, counters);
  return intersectObjects(ray, hit, state) || found;
}

bool SceneAccel::occluded(const Ray& ray, const QueryState& state, TraversalCounters* counters) const {
  if (counters && counters != state.counters) {
    QueryState counted = state;
    counted.counters = counters;
    return occluded(ray, counted);
  }
  counters = state.counters;
  if (layout_ == AccelLayout::Bvh4 || layout_ == AccelLayout::Bvh8) {
    if (occludedWideTriangles(ray, state)) return true;
  } else if (layout_ == AccelLayout::Bvh2) {
    if (!triangleView_.empty() && intersectAny(triangleView_, ray, state, counters)) return true;
  } else if (orientedWide()) {
    if (occludedOrientedWideTriangles(ray, state, counters)) return true;
  } else if (!triangleOrientedView_.empty() && intersectAnyOriented(triangleOrientedView_, ray, state, counters)) {
    return true;
  }
  return occludedObjects(ray, state);
}

uint32_t SceneAccel::intersectPacket(Ray* rays, Hit* hits, uint32_t active, const QueryState& state) const {
  uint32_t found = 0;
  if (layout_ == AccelLayout::Bvh4 && !triangleView4_.empty()) {
    found = intersectClosestWidePacket(triangleView4_, rays, hits, active, state);
  } else if (layout_ == AccelLayout::Bvh8 && !triangleView8_.empty()) {
    found = intersectClosestWidePacket(triangleView8_, rays, hits, active, state);
  } else if (orientedWide() && !triangleOrientedWideView8_.empty() && options_.obbPackets && !state.counters) {
    found = intersectClosestOrientedWidePacket(triangleOrientedWideView8_, rays, hits, active, state);
  } else if (layout_ != AccelLayout::Bvh4 && layout_ != AccelLayout::Bvh8) {
    for (uint32_t m = active; m; m &= m - 1)
      if (intersect(rays[__builtin_ctz(m)], hits[__builtin_ctz(m)], state)) found |= 1u << __builtin_ctz(m);
    return found;
  }
  if (objectBvh_.empty()) return found;
  for (uint32_t m = active; m; m &= m - 1)
    if (intersectObjects(rays[__builtin_ctz(m)], hits[__builtin_ctz(m)], state)) found |= 1u << __builtin_ctz(m);
  return found;
}

uint32_t SceneAccel::occludedPacket(const Ray* rays, uint32_t active, const QueryState& state) const {
  uint32_t blocked = 0;
  if (layout_ == AccelLayout::Bvh4 && !triangleView4_.empty()) {
    blocked = intersectAnyWidePacket(triangleView4_, rays, active, state);
  } else if (layout_ == AccelLayout::Bvh8 && !triangleView8_.empty()) {
    blocked = intersectAnyWidePacket(triangleView8_, rays, active, state);
  } else if (layout_ != AccelLayout::Bvh4 && layout_ != AccelLayout::Bvh8) {
    for (uint32_t m = active; m; m &= m - 1)
      if (occluded(rays[__builtin_ctz(m)], state)) blocked |= 1u << __builtin_ctz(m);
    return blocked;
  }
  if (objectBvh_.empty()) return blocked;
  for (uint32_t m = active & ~blocked; m; m &= m - 1)
    if (occludedObjects(rays[__builtin_ctz(m)], state)) blocked |= 1u << __builtin_ctz(m);
  return blocked;
}

bool SceneAccel::pointQuery(const Vec3f& p, PointQueryCallbacks& callbacks, const PointQueryInstance* instance,
                            float radiusScale) const {
  bool changed = false;
  auto radius = [&] { return callbacks.radius() * radiusScale; };
  // Quads are stored as two triangles and grids as many; the callback must see each quad or grid once
  // (a set: a query with a large radius meets every quad of the scene).
  std::unordered_set<uint64_t> visitedQuads;
  const auto visitTriangle = [&](const StoredTriangle& tri, const std::vector<GridCell>& cells) {
    Box3f b;
    b.extend(tri.v0);
    b.extend(tri.v1);
    b.extend(tri.v2);
    const float r = radius();
    if (!(distanceSquaredToBox(p, b) <= r * r)) return;
    if (isSubdivCell(tri.kind)) return;  // Embree's point queries skip subdivision surfaces
    const uint32_t primID = isGridCell(tri.kind) ? cells[tri.primID].gridPrimID : tri.primID;
    if (tri.kind != TriangleKind::Triangle && !visitedQuads.insert((uint64_t(tri.geomID) << 32) | primID).second) return;
    changed |= callbacks.visit(owner_, tri.geomID, primID, instance);
  };
  const auto visitBlock = [&](const TriangleBlock4& block) {
    for (int lanes = block.usedLanes(); lanes; lanes &= lanes - 1)
      visitTriangle(block.triangle(__builtin_ctz(unsigned(lanes))), gridCells_);
  };
  if (!triangleBvh_.empty()) {
    traverseSphere(triangleBvh_, p, radius, [&](const Bvh2Node& leaf) {
      for (uint32_t i = 0; i < leaf.primCount; ++i) visitTriangle(triangles_[leaf.firstChildOrPrim + i], gridCells_);
    });
  } else if (layout_ == AccelLayout::Bvh8) {
    traverseSphere(triangleBvh8_, p, radius, visitBlock);
  } else if (layout_ == AccelLayout::Bvh4) {
    traverseSphere(triangleBvh4_, p, radius, visitBlock);
  }
  traverseSphere(objectBvh_, p, radius, [&](const Bvh2Node& leaf) {
    for (uint32_t i = 0; i < leaf.primCount; ++i) {
      const ObjectRef& object = objects_[leaf.firstChildOrPrim + i];
      const float r = radius();
      if (!(distanceSquaredToBox(p, object.bounds) <= r * r)) continue;
      if (object.kind == ObjectKind::UserPrimitive) {
        changed |= callbacks.visit(owner_, object.index, object.primID, instance);
        continue;
      }
      if (object.kind == ObjectKind::Shape) continue;  // Embree's point queries skip points and curves
      if (object.kind == ObjectKind::MotionTriangle) {  // where it is at the query's time
        const MotionTriangle& motion = motion_.triangles[object.index];
        StoredTriangle tri;
        if (motion.at(motion_.vertices, callbacks.time(), tri)) visitTriangle(tri, motion_.gridCells);
        continue;
      }
      if (instance) continue;  // one instance level, as for rays
      Instance storage;
      const Instance* placed = placedAt(instances_[object.index], callbacks.time(), storage);
      if (!placed) continue;
      const Instance& inst = *placed;
      const PointQueryInstance frame{inst.geomID, &inst.localToWorld, inst.similarityScale};
      changed |= inst.child->pointQuery(inst.worldToLocal.xfmPoint(p), callbacks, &frame,
                                        radiusScale * inst.radiusToLocal);
    }
  });
  return changed;
}

SceneStats SceneAccel::stats() const {
  SceneStats s;
  s.primitiveCount = triangleCount_ + objects_.size();
  const bool wide = layout_ == AccelLayout::Bvh4 || layout_ == AccelLayout::Bvh8;
  s.nodeCount = (wide ? triangleBvh4_.nodes.size() + triangleBvh8_.nodes.size() : triangleBvh_.nodes.size()) +
                objectBvh_.nodes.size();
  s.leafCount = triangleLeafCount_;
  for (const Bvh2Node& node : objectBvh_.nodes) s.leafCount += node.isLeaf() ? 1 : 0;
  s.memoryBytes = triangleBvh_.nodes.size() * sizeof(Bvh2Node) + triangleBvh4_.nodes.size() * sizeof(Bvh4Node) +
                  triangleBvh8_.nodes.size() * sizeof(Bvh8Node) +
                  (triangleBvh4_.blocks.size() + triangleBvh8_.blocks.size()) * sizeof(TriangleBlock4) +
                  objectBvh_.nodes.size() * sizeof(Bvh2Node) + triangles_.size() * sizeof(StoredTriangle) +
                  objects_.size() * sizeof(ObjectRef) + instances_.size() * sizeof(Instance) +
                  shapes_.size() * sizeof(ShapePrimitive) +
                  geometryMasks_.size() * (sizeof(uint32_t) + 2) +
                  triangleOriented_.nodes.size() * sizeof(OrientedNode) + triangleOriented_.frames.size() * sizeof(Frame) +
                  triangleOrientedWide4_.nodes.size() * sizeof(OrientedWideNode<4>) +
                  triangleOrientedWide8_.nodes.size() * sizeof(OrientedWideNode<8>) +
                  (triangleOrientedWide4_.blocks.size() + triangleOrientedWide8_.blocks.size()) * sizeof(TriangleBlock4);
  for (const auto* blocks : {&triangleBvh4_.blocks, &triangleBvh8_.blocks}) {
    s.leafBlockCount += blocks->size();
    for (const TriangleBlock4& block : *blocks) s.usedBlockLanes += size_t(__builtin_popcount(block.usedLanes()));
  }
  return s;
}

double SceneAccel::statisticsSah() const {
  if (layout_ == AccelLayout::Bvh8) return obvh::statisticsSah(triangleBvh8_);
  if (layout_ == AccelLayout::Bvh4) return obvh::statisticsSah(triangleBvh4_);
  return obvh::statisticsSah(triangleBvh_);
}

LayoutMetrics SceneAccel::triangleLayoutMetrics() const {
  if (layout_ == AccelLayout::Obb || layout_ == AccelLayout::Hybrid) return measureLayout(triangleOriented_, options_);
  if (triangleBvh_.empty() && triangleCount_ > 0)
    throw std::logic_error("triangleLayoutMetrics: the binary tree was released (BuildOptions::keepBinaryTree)");
  return measureLayout(triangleBvh_, options_);
}

}  // namespace obvh
