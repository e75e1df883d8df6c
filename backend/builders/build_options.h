// Parameters of the SAH builders.
#pragma once

#include "math/vec3.h"
#include "obb/obb.h"

namespace obvh {

// How the binary tree is laid out for traversal: axis-aligned boxes (binary, four- or eight-wide),
// an oriented box per node (Obb), or per node whichever of the two is cheaper by SAH (Hybrid).
enum class AccelLayout { Bvh2, Bvh4, Bvh8, Obb, Hybrid };

// How the Obb and Hybrid layouts choose splits: the axis-aligned binned SAH builder, or binned
// SAH, object median or spatial midpoint along the axes of each node's own oriented box.
enum class ObbSplit { AabbSah, Sah, Median, Midpoint };

// rtcSetSceneBuildQuality, for the axis-aligned layouts: Low builds a Morton-code LBVH, Medium
// binned SAH, High adds spatial splits (SBVH). The oriented layouts build as for Medium.
enum class BuildQuality { Low, Medium, High };

// Which builder makes the triangle tree of the axis-aligned layouts: the quality ladder above
// (Sah), or one of the alternatives the benchmark compares with it (device config builder=...).
enum class TreeBuilder { Sah, KMeans, Distance };

// How the wide layouts turn the binary tree into wide nodes (see collapseToWide).
enum class WideCollapse { Greedy, SahOptimal };

// Which triangle test queries use.
enum class IntersectorMode { Watertight, Fast };

// The order in which closest-hit single rays visit the children they enter in the wide layouts:
// near to far (sorted by entry distance), or the node's fixed lane order (larger child first).
enum class ChildOrder { NearToFar, Fixed };

// The leaf size when the device config does not set one (BuildOptions::maxLeafSize = 0). The
// wide layouts let the SAH-driven builders (binned, spatial-split, distance) choose leaves of up
// to seven blocks of four triangles, as Embree's BVH8 leaves allow: on slanted stacks, whose
// overlapping line boxes no split separates, that lowered the SAH cost below Embree's (README,
// build quality ladder). Builders that cut without weighing a leaf (Morton, k-means) and the
// binary layouts keep leaves of up to four.
inline int defaultMaxLeafSize(AccelLayout layout, bool sahDecidesLeaves) {
  return sahDecidesLeaves && (layout == AccelLayout::Bvh4 || layout == AccelLayout::Bvh8) ? 28 : 4;
}

// The eight-wide kernels hold the ray in the identity frame and in each palette frame, one SIMD
// lane a frame (oriented_wide_traverse.h).
constexpr int kMaxPaletteFrames = 7;
// The devices' default for accel=obb|hybrid when obb_clusters is not set: the palette traced
// 1.04-1.27x faster on every slanted stack preset (README, layout study).
constexpr int kDefaultObbPalette = kMaxPaletteFrames;

struct BuildOptions {
  AccelLayout layout = AccelLayout::Bvh4;
  IntersectorMode intersector = IntersectorMode::Watertight;
  ChildOrder childOrder = ChildOrder::NearToFar;
  BuildQuality quality = BuildQuality::Medium;
  float spatialBudget = 1.0f;     // High: extra triangle references allowed, as a fraction of the triangle count
  int binCount = 32;
  int maxLeafSize = 4;            // 0: defaultMaxLeafSize
  float traversalCost = 1.0f;     // relative cost of one node visit
  float intersectionCost = 1.0f;  // relative cost of one primitive test
  TreeBuilder builder = TreeBuilder::Sah;
  int kmeansArity = 8;            // KMeans: clusters per node (the device picks the layout's width)
  float distanceAlpha = 0.5f;     // Distance: weight of the SAH term against the distance term
  Vec3f distanceSource{0.f, 0.f, 0.f};  // Distance: where the rays start
  WideCollapse collapse = WideCollapse::SahOptimal;
  int leafBlockSize = 1;          // primitives tested together (SIMD leaf blocks); the SAH counts whole blocks
  // The wide axis-aligned layouts (bvh4, bvh8) trace only their wide nodes and leaf blocks: the
  // binary tree they were collapsed from is released after the collapse, and no copy of the
  // triangles in its leaf order is made (together about half of what a committed scene held),
  // unless both are kept for a refit (RTC_BUILD_QUALITY_REFIT, SceneAccel::refit) or the layout
  // study (triangleLayoutMetrics).
  bool keepBinaryTree = false;
  // Oriented layouts.
  ObbSplit obbSplit = ObbSplit::AabbSah;  // measured best on every slanted stack preset (README)
  int obbBins = 32;
  ObbFit obbFit = ObbFit::Dito14;  // PCA for comparison (the layout study)
  float obbTestCost = 2.0f;       // cost of one oriented-box test relative to traversalCost (one AABB test)
  int obbClusters = 0;            // k-means clusters of leaf box frames; 0 = every leaf keeps its own
  int obbPalette = 0;             // shared frames every oriented node picks from (1..kMaxPaletteFrames); 0 = own frames
  int obbWidth = 4;               // children a node when traced: 2 (the binary tree), 4 or 8 (oriented_wide_bvh.h; 8 needs AVX2)
  // Closest-hit packets through eight-wide oriented trees traced together (oriented_wide_packets.h)
  // instead of ray by ray (obb_packets=off): 4-16% faster on the stack presets' camera packets
  // except diagonal-42k's (13% / 5% slower; README, layout study).
  bool obbPackets = true;
};

}  // namespace obvh
