// The neighbouring float below x, as std::nextafter(x, -inf) gives it, without the libm call
// (the traversal asks after every hit; nextafterf is not inlined).
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>

namespace obvh {

inline float nextFloatDown(float x) {
  if (!(x > -std::numeric_limits<float>::infinity())) return x;  // NaN and -inf stay
  if (x == 0.f) return -std::numeric_limits<float>::denorm_min();  // from +0 and -0 alike
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits = x > 0.f ? bits - 1 : bits + 1;  // one step of the magnitude, towards -inf
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

}  // namespace obvh
