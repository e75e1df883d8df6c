// A std::allocator whose element construction without arguments default-initializes instead of
// value-initializing: resize() of a vector of plain records then leaves them unwritten (no
// zero fill), and the parallel writers that fill them are the first to touch their pages.
#pragma once

#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace obvh {

template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}

  template <class U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using DefaultInitVector = std::vector<T, DefaultInitAllocator<T>>;

}  // namespace obvh
