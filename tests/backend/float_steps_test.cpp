// nextFloatDown against std::nextafter(x, -inf): every special value and a sweep of bit patterns.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "math/float_steps.h"

namespace obvh {
namespace {

uint32_t bitsOf(float x) {
  uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

void expectSameAsNextafter(float x) {
  const float expected = std::nextafter(x, -std::numeric_limits<float>::infinity());
  const float actual = nextFloatDown(x);
  if (std::isnan(expected)) {
    EXPECT_TRUE(std::isnan(actual)) << x;
    return;
  }
  EXPECT_EQ(bitsOf(actual), bitsOf(expected)) << "x = " << x << " (bits " << bitsOf(x) << ")";
}

TEST(FloatSteps, SpecialValues) {
  using L = std::numeric_limits<float>;
  for (float x : {0.f, -0.f, L::denorm_min(), -L::denorm_min(), L::min(), -L::min(), 1.f, -1.f, L::max(),
                  -L::max(), L::infinity(), -L::infinity(), L::quiet_NaN()})
    expectSameAsNextafter(x);
}

TEST(FloatSteps, EveryFourThousandthBitPattern) {
  for (uint64_t bits = 0; bits <= 0xFFFFFFFFu; bits += 4093) {
    const uint32_t b = uint32_t(bits);
    float x;
    std::memcpy(&x, &b, sizeof x);
    expectSameAsNextafter(x);
  }
}

}  // namespace
}  // namespace obvh
