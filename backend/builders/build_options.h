// Parameters of the SAH builders.
#pragma once

namespace obvh {

// How the binary tree is laid out for traversal.
enum class AccelLayout { Bvh2, Bvh4 };

// Which triangle test queries use.
enum class IntersectorMode { Watertight, Fast };

struct BuildOptions {
  AccelLayout layout = AccelLayout::Bvh4;
  IntersectorMode intersector = IntersectorMode::Watertight;
  int binCount = 32;
  int maxLeafSize = 4;
  float traversalCost = 1.0f;     // relative cost of one node visit
  float intersectionCost = 1.0f;  // relative cost of one primitive test
};

}  // namespace obvh
