// A std::allocator that leaves elements unwritten when a vector adds them without a value
// (resize, the size constructor), for tables of plain records that are each written before they
// are read: a build's triangles and refs, the wide nodes and leaf blocks, the collapse's plans.
// The loops that fill them, parallel ones mostly, are then the first to touch their pages, and
// nothing writes them twice. The value-initializing resizes of the dragon's triangles and refs
// took 14 ms on one thread, most of it the kernel clearing fresh pages, which the first touch
// still pays: builds ran only 1.00-1.03x as fast without them (paired build timing).
#pragma once

#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace obvh {

template <class T>
struct UnwrittenAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UnwrittenAllocator<U>;
  };
  UnwrittenAllocator() = default;
  template <class U>
  UnwrittenAllocator(const UnwrittenAllocator<U>&) noexcept {}

  // Records of this kind begin to exist in the allocated storage without a constructor running.
  template <class U>
  void construct(U*) noexcept {
    static_assert(std::is_trivially_copyable_v<U> && std::is_trivially_destructible_v<U>);
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using UnwrittenVector = std::vector<T, UnwrittenAllocator<T>>;

}  // namespace obvh
