// A parallel reduction whose result does not depend on the number of threads: the range is cut
// into fixed blocks and the per-block results merge in a fixed order. Builders that sum floating
// point values (centroids) use it so that the same input gives the same tree on any machine.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <cstddef>

namespace obvh {

// body(begin, end, T& accumulator) adds [begin, end) to accumulator; T has merge(const T&).
// Ranges up to sequentialLimit run on the calling thread.
template <class T, class Body>
T reduceDeterministically(size_t begin, size_t end, const Body& body, size_t sequentialLimit = size_t(1) << 14,
                          size_t block = 4096) {
  if (end - begin <= sequentialLimit) {
    T result{};
    body(begin, end, result);
    return result;
  }
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(begin, end, block), T{},
      [&](const tbb::blocked_range<size_t>& r, T acc) {
        body(r.begin(), r.end(), acc);
        return acc;
      },
      [](T a, const T& b) {
        a.merge(b);
        return a;
      });
}

}  // namespace obvh
