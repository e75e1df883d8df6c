// Large build arrays are first touched one 4 KiB page at a time, and in a virtual machine every
// page fault is expensive (perf: about a fifth of a cold bvh8 build of the OpenFOAM buildings).
// Advising transparent huge pages on a fresh, untouched reservation lets the kernel map 2 MiB at
// a time where it allows (THP "madvise" mode, Debian's default), as Embree's allocator does.
#pragma once

#include <cstddef>
#include <vector>

namespace obvh {

// Advises huge pages for the 2 MiB-aligned part of [data, data + bytes); small ranges are left.
void adviseHugePages(void* data, size_t bytes);

// v.reserve(n), with the new storage advised for huge pages before anything touches it.
template <class T, class Allocator>
void reserveWithHugePages(std::vector<T, Allocator>& v, size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(n);
  adviseHugePages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace obvh
