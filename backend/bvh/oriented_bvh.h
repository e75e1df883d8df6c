// Binary BVH whose nodes are bounded either by an axis-aligned box or by an oriented box (the
// layouts accel=obb and accel=hybrid). Oriented nodes refer to a shared table of frames, so
// clustered leaves can share one frame and the ray's transform into it.
#pragma once

#include <cstdint>
#include <vector>

#include "math/vec3.h"

namespace obvh {

struct Frame {
  Vec3f axis[3];  // orthonormal rows: box coordinates of p are dot(axis[k], p)
};

// 40 bytes.
struct OrientedNode {
  static constexpr uint32_t kAxisAligned = 0xFFFFFFFFu;
  Vec3f lower, upper;             // the box in its frame's coordinates (world when axis-aligned)
  uint32_t frame = kAxisAligned;  // index into OrientedBvh::frames
  float magnitude = 0.f;          // bound on |p| over the box: rounding margins scale with it
  uint32_t firstChildOrPrim = 0;  // interior: left child (right = left + 1); leaf: first primitive
  uint32_t primCount = 0;         // 0 marks an interior node
  bool isLeaf() const { return primCount != 0; }
  bool oriented() const { return frame != kAxisAligned; }
};

struct OrientedBvh {
  std::vector<OrientedNode> nodes;  // nodes[0] is the root
  std::vector<Frame> frames;
  // obb_palette: frames [0, paletteFrames) are shared by the oriented nodes whose boxes fit about as
  // tightly in one of them as in their own frame (at most kMaxPaletteFrames); the others follow.
  uint32_t paletteFrames = 0;
  bool empty() const { return nodes.empty(); }
};

// What a layout costs and how it is shaped, for the metrics report.
struct LayoutMetrics {
  double sahCost = 0.0;       // expected cost per ray: node tests (AABB = 1, OBB = obbTestCost) + triangle tests
  double depthStdDev = 0.0;   // of the leaves' depths
  double meanLeafDepth = 0.0;
  size_t nodeCount = 0, leafCount = 0, orientedNodeCount = 0, frameCount = 0;
  size_t memoryBytes = 0;
};

}  // namespace obvh
