// The watertight test's per-ray constants made other ways than by the constructor every other
// path uses, against it: without branches (WatertightRay::withoutBranches, the axis-aligned wide
// kernels' set-up) and for a lane group of rays at once (watertightFramesOfLanes, the packet
// kernels' set-up, in each lane type: the scalar reference, SSE, AVX2). The same axis order and bit
// for bit the same floats, for directions with ties between axes, signed zeros, denormals,
// infinities and NaNs as well as random ones, with tnear zero, positive, infinite and NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "float_bits.h"
#include "intersect/ray.h"
#include "intersect/watertight_triangle.h"
#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "intersect/watertight_lanes.h"

namespace obvh {
namespace {

// Each lane type's frames are made inside one function compiled for its instruction set.
void framesScalar4(const Ray* rays, WatertightRay* frames, uint32_t wanted) {
  watertightFramesOfLanes<simd::FloatScalar<4>>(rays, frames, wanted);
}
void framesScalar8(const Ray* rays, WatertightRay* frames, uint32_t wanted) {
  watertightFramesOfLanes<simd::FloatScalar<8>>(rays, frames, wanted);
}
void framesSse(const Ray* rays, WatertightRay* frames, uint32_t wanted) {
  watertightFramesOfLanes<simd::Float4Sse>(rays, frames, wanted);
}

}  // namespace
}  // namespace obvh

#pragma GCC push_options
#pragma GCC target("avx2")
#include "simd/float8_avx.h"
namespace obvh {
namespace {
void framesAvx(const Ray* rays, WatertightRay* frames, uint32_t wanted) {
  watertightFramesOfLanes<simd::Float8Avx>(rays, frames, wanted);
}
}  // namespace
}  // namespace obvh
#pragma GCC pop_options

namespace obvh {
namespace {

using test::sameBits;

std::string describe(const Ray& ray) {
  return "dir (" + std::to_string(ray.dir.x) + ", " + std::to_string(ray.dir.y) + ", " + std::to_string(ray.dir.z) +
         "), tnear " + std::to_string(ray.tnear);
}

void expectSameFrame(const WatertightRay& candidate, const Ray& ray, const std::string& where) {
  const WatertightRay reference(ray);
  ASSERT_EQ(candidate.kx, reference.kx) << where;
  ASSERT_EQ(candidate.ky, reference.ky) << where;
  ASSERT_EQ(candidate.kz, reference.kz) << where;
  ASSERT_TRUE(sameBits(candidate.Sx, reference.Sx)) << where;
  ASSERT_TRUE(sameBits(candidate.Sy, reference.Sy)) << where;
  ASSERT_TRUE(sameBits(candidate.Sz, reference.Sz)) << where;
  ASSERT_TRUE(sameBits(candidate.nearAlongKz, reference.nearAlongKz)) << where;
  for (int axis = 0; axis < 3; ++axis) ASSERT_TRUE(sameBits(candidate.org[axis], reference.org[axis])) << where;
}

void expectWithoutBranchesMatches(const std::vector<Ray>& rays) {
  for (const Ray& ray : rays) expectSameFrame(WatertightRay::withoutBranches(ray), ray, describe(ray));
}

// The rays in groups of `lanes`, each group's frames made with `wanted` all lanes but one that
// varies (so the unwanted lane's frame, which is unspecified, is skipped), against the constructor.
void expectSameFramesOfLanes(const std::vector<Ray>& rays, int lanes,
                             void (*framesOfLanes)(const Ray*, WatertightRay*, uint32_t)) {
  for (size_t first = 0; first + size_t(lanes) <= rays.size(); first += size_t(lanes)) {
    const int skipped = int(first / size_t(lanes)) % (lanes + 1);  // == lanes: none skipped
    const uint32_t wanted = ((1u << lanes) - 1) & ~(1u << skipped);
    WatertightRay frames[8];
    framesOfLanes(rays.data() + first, frames, wanted);
    for (int lane = 0; lane < lanes; ++lane) {
      if (!((wanted >> lane) & 1)) continue;
      const Ray& ray = rays[first + size_t(lane)];
      expectSameFrame(frames[lane], ray,
                      describe(ray) + ", lanes " + std::to_string(lanes) + ", lane " + std::to_string(lane));
    }
  }
}

void expectEveryLaneTypeMatches(const std::vector<Ray>& rays) {
  expectSameFramesOfLanes(rays, 4, framesScalar4);
  expectSameFramesOfLanes(rays, 8, framesScalar8);
  expectSameFramesOfLanes(rays, 4, framesSse);
  if (simd::cpuHasAvx2()) expectSameFramesOfLanes(rays, 8, framesAvx);
}

std::vector<Ray> raysOfSpecialDirections() {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[] = {0.f, -0.f, 1.f, -1.f, 2.f, -2.f, 1e-40f, -1e-40f, inf, -inf, nan, 0.5f, -3.f};
  const float tnears[] = {0.f, 0.25f, 1e-40f, inf, nan, 3e38f};
  std::vector<Ray> rays;
  int k = 0;
  for (float x : values)
    for (float y : values)
      for (float z : values) {
        Ray ray;
        ray.org = {0.25f * float(k % 7), -7.f, 1e6f - float(k)};
        ray.tnear = tnears[k % 6];
        ray.dir = {x, y, z};
        rays.push_back(ray);
        ++k;
      }
  return rays;
}

std::vector<Ray> raysOfRandomDirections(size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coordinate(-1.f, 1.f);
  std::uniform_int_distribution<int> tie(0, 7);
  std::vector<Ray> rays(count);
  for (Ray& ray : rays) {
    ray.org = {coordinate(rng) * 100.f, coordinate(rng), coordinate(rng) * 1e-3f};
    ray.tnear = tie(rng) < 4 ? 0.f : std::fabs(coordinate(rng)) * 1e-3f;
    ray.dir = {coordinate(rng), coordinate(rng), coordinate(rng)};
    // Some directions with two or three components of the same magnitude (the comparisons' ties).
    const int t = tie(rng);
    if (t == 1) ray.dir.y = std::copysign(ray.dir.x, ray.dir.y);
    if (t == 2) ray.dir.z = std::copysign(ray.dir.y, ray.dir.z);
    if (t == 3) ray.dir.z = std::copysign(ray.dir.x, ray.dir.z);
    if (t == 4) ray.dir.y = ray.dir.z = ray.dir.x;
  }
  return rays;
}

TEST(WatertightRay, WithoutBranchesMatchesTheConstructorOnSpecialDirections) {
  expectWithoutBranchesMatches(raysOfSpecialDirections());
}

TEST(WatertightRay, WithoutBranchesMatchesTheConstructorOnRandomDirections) {
  expectWithoutBranchesMatches(raysOfRandomDirections(100000, 2026));
}

TEST(WatertightRay, LanesMatchTheConstructorOnSpecialDirections) {
  expectEveryLaneTypeMatches(raysOfSpecialDirections());
}

TEST(WatertightRay, LanesMatchTheConstructorOnRandomDirections) {
  expectEveryLaneTypeMatches(raysOfRandomDirections(40000, 2044));
}

}  // namespace
}  // namespace obvh
