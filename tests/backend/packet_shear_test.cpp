// The packet leaf's shear (PacketShear), made for a packet's rays at once as SIMD lanes, against
// each ray's own watertight frame (WatertightRay): the same axis order, or not usable when the rays
// do not share one, and bit for bit the same origins and shear constants in every live lane.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"
#include "traversal/triangle_packet_leaf.h"

namespace obvh {
namespace {

struct ShearLanes {
  bool usable = false;
  int axes[3] = {0, 1, 2};
  float org[3][kMaxPacketSize] = {}, Sx[kMaxPacketSize] = {}, Sy[kMaxPacketSize] = {};
  WatertightRay frames[kMaxPacketSize];  // PacketShear::frame of each live ray
};

// Always inlined, so that each ISA's shear is compiled for that ISA (see avxShear).
template <typename FR>
[[gnu::always_inline]] inline ShearLanes shearOf(const Ray* rays, uint32_t live) {
  const PacketShear<FR> shear(rays, live);
  ShearLanes s;
  s.usable = shear.usable;
  if (!s.usable) return s;
  std::memcpy(s.axes, shear.axes, sizeof s.axes);
  std::memcpy(s.org, shear.org, sizeof s.org);
  std::memcpy(s.Sx, shear.Sx, sizeof s.Sx);
  std::memcpy(s.Sy, shear.Sy, sizeof s.Sy);
  for (uint32_t m = live; m; m &= m - 1) {
    const int r = __builtin_ctz(m);
    s.frames[r] = shear.frame(rays[r], r);
  }
  return s;
}

ShearLanes sseShear(const Ray* rays, uint32_t live) { return shearOf<simd::Float4Sse>(rays, live); }
ShearLanes scalarShear(const Ray* rays, uint32_t live) { return shearOf<simd::FloatScalar<8>>(rays, live); }

}  // namespace
}  // namespace obvh

// The eight-wide lanes in a function compiled for AVX2 (no vector value crosses between targets).
#pragma GCC push_options
#pragma GCC target("avx2")
#include "simd/float8_avx.h"
namespace obvh {
namespace {
ShearLanes avxShear(const Ray* rays, uint32_t live) { return shearOf<simd::Float8Avx>(rays, live); }
}  // namespace
}  // namespace obvh
#pragma GCC pop_options

namespace obvh {
namespace {

bool sameFloat(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

// Packets of 16 rays: most share a dominant axis and its sign (camera rays), with components that
// tie with the dominant one, zeros of either sign, and now and then a ray that breaks the order.
std::vector<Ray> packetRays(std::mt19937& rng, int packet) {
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  std::uniform_int_distribution<int> pick(0, 15);
  const int dominant = packet % 3;
  const float sign = (packet / 3) % 2 ? -1.f : 1.f;
  std::vector<Ray> rays(kMaxPacketSize);
  for (int r = 0; r < kMaxPacketSize; ++r) {
    Ray& ray = rays[r];
    for (int axis = 0; axis < 3; ++axis) ray.org[axis] = 100.f * unit(rng);
    ray.tnear = 0.f;
    ray.tfar = 1e30f;
    for (int axis = 0; axis < 3; ++axis) ray.dir[axis] = 0.9f * unit(rng);
    ray.dir[dominant] = sign * (1.f + 0.5f * std::fabs(unit(rng)));
    const int kind = pick(rng);
    const int other = (dominant + 1 + kind % 2) % 3;
    if (kind == 0) ray.dir[other] = ray.dir[dominant];   // a tie, same sign
    if (kind == 1) ray.dir[other] = -ray.dir[dominant];  // a tie, other sign
    if (kind == 2) ray.dir[other] = 0.f;
    if (kind == 3) ray.dir[other] = -0.f;
    if (kind == 4 && packet % 4 == 0) ray.dir[other] = 3.f;        // another dominant axis
    if (kind == 5 && packet % 5 == 0) ray.dir[dominant] = -ray.dir[dominant];  // the other sign
  }
  return rays;
}

void expectShearOfEveryRay(const char* isa, ShearLanes (*make)(const Ray*, uint32_t)) {
  std::mt19937 rng(2026);
  int usable = 0, unusable = 0;
  for (int packet = 0; packet < 600; ++packet) {
    const std::vector<Ray> rays = packetRays(rng, packet);
    const uint32_t live = packet % 7 == 0 ? 0xFF00u : packet % 3 == 0 ? 0xFFFFu : (rng() & 0xFFFFu) | 1u;
    const ShearLanes s = make(rays.data(), live);
    bool shared = true;
    const WatertightRay first(rays[__builtin_ctz(live)]);
    for (uint32_t m = live; m; m &= m - 1) {
      const WatertightRay f(rays[__builtin_ctz(m)]);
      shared &= f.kx == first.kx && f.ky == first.ky && f.kz == first.kz;
    }
    ASSERT_EQ(s.usable, shared) << isa << " packet " << packet;
    (shared ? usable : unusable)++;
    if (!shared) continue;
    EXPECT_EQ(s.axes[0], first.kx) << isa << " packet " << packet;
    EXPECT_EQ(s.axes[1], first.ky) << isa << " packet " << packet;
    EXPECT_EQ(s.axes[2], first.kz) << isa << " packet " << packet;
    for (uint32_t m = live; m; m &= m - 1) {
      const int r = __builtin_ctz(m);
      const WatertightRay f(rays[r]);
      for (int a = 0; a < 3; ++a)
        EXPECT_TRUE(sameFloat(s.org[a][r], f.org[s.axes[a]])) << isa << " packet " << packet << " ray " << r;
      EXPECT_TRUE(sameFloat(s.Sx[r], f.Sx)) << isa << " packet " << packet << " ray " << r << ": " << s.Sx[r]
                                             << " vs " << f.Sx;
      EXPECT_TRUE(sameFloat(s.Sy[r], f.Sy)) << isa << " packet " << packet << " ray " << r << ": " << s.Sy[r]
                                             << " vs " << f.Sy;
      // The frame made from the lanes is the ray's own, field for field.
      const WatertightRay& w = s.frames[r];
      EXPECT_TRUE(w.kx == f.kx && w.ky == f.ky && w.kz == f.kz) << isa << " packet " << packet << " ray " << r;
      EXPECT_TRUE(sameFloat(w.Sx, f.Sx) && sameFloat(w.Sy, f.Sy) && sameFloat(w.Sz, f.Sz))
          << isa << " packet " << packet << " ray " << r << ": Sz " << w.Sz << " vs " << f.Sz;
      for (int a = 0; a < 3; ++a)
        EXPECT_TRUE(sameFloat(w.org[a], f.org[a])) << isa << " packet " << packet << " ray " << r;
    }
  }
  // Both outcomes are exercised.
  EXPECT_GT(usable, 100);
  EXPECT_GT(unusable, 100);
}

TEST(PacketShear, MatchesEveryRaysWatertightFrame) {
  expectShearOfEveryRay("scalar", scalarShear);
  expectShearOfEveryRay("sse", sseShear);
  if (simd::cpuHasAvx2()) expectShearOfEveryRay("avx2", avxShear);
}

}  // namespace
}  // namespace obvh
