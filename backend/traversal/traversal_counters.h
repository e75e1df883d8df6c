// Optional counts of what one traversal did, for the layout metrics and heatmaps. Traversals take
// a pointer that is null on the normal query path.
#pragma once

#include <cstdint>

namespace obvh {

struct TraversalCounters {
  uint64_t aabbTests = 0;
  uint64_t obbTests = 0;
  uint64_t leafVisits = 0;
  uint64_t volumeTests() const { return aabbTests + obbTests; }
};

}  // namespace obvh
