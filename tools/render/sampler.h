// Deterministic per-pixel random numbers (PCG32, O'Neill 2014): the same pixel, sample and frame
// draw the same sequence whichever library traces the rays, so images can be compared exactly.
#pragma once

#include <cstdint>

namespace obvh::render {

class Sampler {
 public:
  Sampler(uint64_t pixel, uint64_t sample, uint64_t frame) {
    state_ = 0u;
    increment_ = (mix(pixel * 0x9E3779B97F4A7C15ull ^ frame) << 1u) | 1u;
    next();
    state_ += mix(sample + 0x632BE59BD9B4E019ull * (pixel + 1));
    next();
  }
  // Uniform in [0, 1).
  float next1D() { return float(next() >> 8) * (1.f / 16777216.f); }

 private:
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const uint32_t shifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rotation = uint32_t(old >> 59u);
    return (shifted >> rotation) | (shifted << ((32u - rotation) & 31u));
  }
  uint64_t state_ = 0, increment_ = 1;
};

}  // namespace obvh::render
