// Storage for a short array of trivially copyable records that are each assigned before they are
// read, without running their default member initializers: per-packet scratch arrays (16 rays,
// hits, frames) are set up once per query, and initializing every slot cost as much as filling
// the few used ones.
#pragma once

#include <cstddef>
#include <type_traits>

namespace obvh {

template <typename T, size_t N>
union UninitializedArray {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  T items[N];

  UninitializedArray() {}
  T& operator[](size_t i) { return items[i]; }
  const T& operator[](size_t i) const { return items[i]; }
  T* data() { return items; }
  const T* data() const { return items; }
};

}  // namespace obvh
