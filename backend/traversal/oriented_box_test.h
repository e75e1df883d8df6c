// Ray against a node of the oriented layouts. An oriented node transforms the ray into its frame
// and runs the conservative slab test there; the box is widened by a margin that covers the
// rounding of that transform (origin and direction, each component a three-term dot product)
// for any point the exact ray can reach inside the box, so rounding never culls a real hit.
#pragma once

#include "bvh/oriented_bvh.h"
#include "traversal/box_test.h"
#include "traversal/traversal_counters.h"

namespace obvh {

// Margin per unit of |origin|_1 + |box|: each transformed coordinate is off by at most
// gamma(3) * (|o|_1 + t |d|_1), and the t that reach the box have t |d| <= |o| + |box|.
constexpr float kObbMarginScale = 4.f * gammaBound(3);

// Per-ray state: the world-space slab test data and the ray transformed into the last frame used.
class OrientedRay {
 public:
  explicit OrientedRay(const Ray& ray)
      : world_(ray), ray_(ray), local_(ray),
        originNorm_(std::fabs(ray.org.x) + std::fabs(ray.org.y) + std::fabs(ray.org.z)) {}

  // Entry distance into the node's volume within [tnear, tfar], or +inf.
  float enter(const OrientedNode& node, const Frame* frames, float tnear, float tfar, TraversalCounters* counters) {
    if (!node.oriented()) {
      if (counters) ++counters->aabbTests;
      return intersectBox(world_, Box3f{node.lower, node.upper}, tnear, tfar);
    }
    if (counters) ++counters->obbTests;
    if (node.frame != cachedFrame_) {
      const Frame& f = frames[node.frame];
      Ray local = ray_;
      local.org = {dot(f.axis[0], ray_.org), dot(f.axis[1], ray_.org), dot(f.axis[2], ray_.org)};
      local.dir = {dot(f.axis[0], ray_.dir), dot(f.axis[1], ray_.dir), dot(f.axis[2], ray_.dir)};
      local_ = BoxRay(local);
      cachedFrame_ = node.frame;
    }
    const float margin = kObbMarginScale * (2.f * originNorm_ + 2.f * node.magnitude);
    const Vec3f m{margin, margin, margin};
    return intersectBox(local_, Box3f{node.lower - m, node.upper + m}, tnear, tfar);
  }

 private:
  BoxRay world_;
  Ray ray_;
  BoxRay local_;
  float originNorm_;
  uint32_t cachedFrame_ = OrientedNode::kAxisAligned;
};

}  // namespace obvh
