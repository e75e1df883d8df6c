// Parameters of the SAH builders.
#pragma once

namespace obvh {

struct BuildOptions {
  int binCount = 32;
  int maxLeafSize = 4;
  float traversalCost = 1.0f;     // relative cost of one node visit
  float intersectionCost = 1.0f;  // relative cost of one primitive test
};

}  // namespace obvh
