// Hints that bring memory a query is about to read into the first-level cache: no fault and no
// effect on any result, only on when the lines arrive.
#pragma once

#include <cstddef>
#include <cstdint>

namespace obvh {

// Every cache line of [p, p + bytes).
[[gnu::always_inline]] inline void prefetchBytes(const void* p, size_t bytes) {
  constexpr uintptr_t kLine = 64;
  if (bytes == 0) return;
  const uintptr_t first = reinterpret_cast<uintptr_t>(p) & ~(kLine - 1);
  const uintptr_t last = reinterpret_cast<uintptr_t>(p) + bytes - 1;
  for (uintptr_t line = first; line <= last; line += kLine) __builtin_prefetch(reinterpret_cast<const void*>(line), 0, 3);
}

}  // namespace obvh
