// The watertight test's per-ray constants made without branches (WatertightRay::withoutBranches,
// the axis-aligned wide kernels' set-up) against the constructor every other path uses: the same
// axis order and bit for bit the same shear constants, for directions with ties between axes, signed
// zeros, denormals, infinities and NaNs as well as random ones.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "float_bits.h"
#include "intersect/watertight_triangle.h"

namespace obvh {
namespace {

using test::sameBits;

void expectSameFrame(const Ray& ray) {
  const WatertightRay reference(ray);
  const WatertightRay candidate = WatertightRay::withoutBranches(ray);
  const std::string where = "dir (" + std::to_string(ray.dir.x) + ", " + std::to_string(ray.dir.y) + ", " +
                            std::to_string(ray.dir.z) + ")";
  EXPECT_EQ(candidate.kx, reference.kx) << where;
  EXPECT_EQ(candidate.ky, reference.ky) << where;
  EXPECT_EQ(candidate.kz, reference.kz) << where;
  EXPECT_TRUE(sameBits(candidate.Sx, reference.Sx)) << where;
  EXPECT_TRUE(sameBits(candidate.Sy, reference.Sy)) << where;
  EXPECT_TRUE(sameBits(candidate.Sz, reference.Sz)) << where;
  for (int axis = 0; axis < 3; ++axis) EXPECT_TRUE(sameBits(candidate.org[axis], reference.org[axis])) << where;
}

TEST(WatertightRay, WithoutBranchesMatchesTheConstructorOnSpecialDirections) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.f, -0.f, 1.f, -1.f, 2.f, -2.f, 1e-40f, -1e-40f, inf, -inf, nan, 0.5f, -3.f};
  Ray ray;
  ray.org = {0.25f, -7.f, 1e6f};
  for (float x : values)
    for (float y : values)
      for (float z : values) {
        ray.dir = {x, y, z};
        expectSameFrame(ray);
      }
}

TEST(WatertightRay, WithoutBranchesMatchesTheConstructorOnRandomDirections) {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<float> coordinate(-1.f, 1.f);
  std::uniform_int_distribution<int> tie(0, 7);
  Ray ray;
  for (int i = 0; i < 100000; ++i) {
    ray.org = {coordinate(rng) * 100.f, coordinate(rng), coordinate(rng) * 1e-3f};
    ray.dir = {coordinate(rng), coordinate(rng), coordinate(rng)};
    // Some directions with two or three components of the same magnitude (the comparisons' ties).
    const int t = tie(rng);
    if (t == 1) ray.dir.y = std::copysign(ray.dir.x, ray.dir.y);
    if (t == 2) ray.dir.z = std::copysign(ray.dir.y, ray.dir.z);
    if (t == 3) ray.dir.z = std::copysign(ray.dir.x, ray.dir.z);
    if (t == 4) ray.dir.y = ray.dir.z = ray.dir.x;
    expectSameFrame(ray);
  }
}

}  // namespace
}  // namespace obvh
