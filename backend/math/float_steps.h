// The neighbouring float below x, as std::nextafter(x, -inf) gives it, without the libm call
// (the traversal asks after every hit; nextafterf is not inlined).
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>

namespace obvh {

inline float nextFloatDown(float x) {
  uint32_t bits;
  // Positive x first, one compare: the walks step below every hit's distance, which lies beyond a
  // tnear of +0 or more (tested last, the case took about 11 instructions at each leaf a ray left).
  if (x > 0.f) {
    std::memcpy(&bits, &x, sizeof bits);
    bits -= 1;
    std::memcpy(&x, &bits, sizeof x);
    return x;
  }
  if (!(x > -std::numeric_limits<float>::infinity())) return x;  // NaN and -inf stay
  if (x == 0.f) return -std::numeric_limits<float>::denorm_min();  // from +0 and -0 alike
  std::memcpy(&bits, &x, sizeof bits);
  bits += 1;  // negative x: one step of the magnitude up, towards -inf
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

}  // namespace obvh
