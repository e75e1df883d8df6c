// The single-ray traversals' stack entry: a node and the distance at which the ray enters it.
#pragma once

#include <cstdint>
#include <cstring>

namespace obvh {

// A stack entry packed into one 64-bit word and written with one store: an entry is often popped
// right after it was pushed (the nearer child's box test fails), and reading eight bytes written as
// two four-byte stores stalls on store forwarding.
class StackEntry {
 public:
  StackEntry() = default;
  StackEntry(uint32_t child, float t) {
    uint32_t tBits;
    std::memcpy(&tBits, &t, sizeof tBits);
    bits_ = uint64_t(child) | uint64_t(tBits) << 32;
  }
  uint32_t child() const { return uint32_t(bits_); }
  float t() const {
    const uint32_t tBits = uint32_t(bits_ >> 32);
    float t;
    std::memcpy(&t, &tBits, sizeof t);
    return t;
  }

 private:
  uint64_t bits_;
};

}  // namespace obvh
