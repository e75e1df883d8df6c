// The fallback split of the alternative builders: half the primitives on each side along the
// widest axis of their centroids, ties broken by primitive index (the same tree on any machine).
#pragma once

#include <algorithm>
#include <vector>

#include "builders/prim_ref.h"

namespace obvh {

// Reorders refs[begin, end) and returns the first index of the upper half.
inline size_t splitAtObjectMedian(PrimRefs& refs, size_t begin, size_t end, const Box3f& centroidBounds) {
  const int axis = centroidBounds.largestAxis();
  const size_t middle = begin + (end - begin) / 2;
  std::nth_element(refs.begin() + long(begin), refs.begin() + long(middle), refs.begin() + long(end),
                   [axis](const PrimRef& a, const PrimRef& b) {
                     const float ca = a.bounds.center2()[axis], cb = b.bounds.center2()[axis];
                     return ca < cb || (ca == cb && a.index < b.index);
                   });
  return middle;
}

}  // namespace obvh
