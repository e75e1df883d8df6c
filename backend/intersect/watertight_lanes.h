// The watertight test's per-ray constants (WatertightRay) for a lane group of rays at once, as
// SIMD lanes (FN: the packet kernels' float type). Each lane makes the same comparisons, the same
// choices and the same divisions as WatertightRay's constructor, so every frame is the one the
// constructor makes, bit for bit. A packet's rays that reach leaves each made their frame alone:
// a branchy choice of axes and three scalar divisions a ray, about 230 of the 2,770 instructions a
// coherent rtcIntersect8 packet took in the library on the bunny (callgrind, averaged over all
// packets); made as lanes, the packets traced 1.03-1.04x as fast (paired ladder).
// Templates only, included inside the per-ISA target regions like the kernels that use them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "intersect/ray.h"
#include "intersect/watertight_triangle.h"

namespace obvh {

// frames[i] = WatertightRay(rays[i]) for the rays of `wanted` (bit i: rays[i]), i < FN::kWidth.
// Every lane of the group is read and written: rays[0..kWidth) must be readable (idle lanes may
// be uninitialized) and frames[0..kWidth) writable; the frames of lanes outside wanted are
// unspecified.
template <typename FN>
[[gnu::always_inline]] inline void watertightFramesOfLanes(const Ray* rays, WatertightRay* frames, uint32_t wanted) {
  constexpr int kLanes = FN::kWidth;
  static_assert(8 % kLanes == 0);
  static_assert(offsetof(Ray, org) == 0 && offsetof(Ray, tnear) == 3 * sizeof(float) &&
                    offsetof(Ray, dir) == 4 * sizeof(float) && sizeof(Ray) % sizeof(float) == 0,
                "a ray's first eight floats are org, tnear, dir (and time)");
  static_assert(offsetof(WatertightRay, Sx) == 0 && offsetof(WatertightRay, Sy) == 4 &&
                    offsetof(WatertightRay, Sz) == 8 && offsetof(WatertightRay, org) == 12 &&
                    offsetof(WatertightRay, nearAlongKz) == 24 && offsetof(WatertightRay, kz) == 28 &&
                    offsetof(WatertightRay, kx) == 32 && offsetof(WatertightRay, ky) == 36 &&
                    sizeof(WatertightRay) == 40 && sizeof(WatertightAxisPair) == 8,
                "seven floats, kz, then kx and ky");
  FN leading[8];  // org x, y, z, tnear, dir x, y, z, time
  for (int c = 0; c < 8; c += kLanes)
    FN::loadColumns(reinterpret_cast<const float*>(rays) + c, sizeof(Ray) / sizeof(float), leading + c);
  const FN& dx = leading[4];
  const FN& dy = leading[5];
  const FN& dz = leading[6];
  const FN ax = abs(dx), ay = abs(dy), az = abs(dz);
  // The constructor's kz: x where |x| >= |y| and |x| >= |z|, else y where |y| >= |z|, else z
  // (NaNs fail every comparison: z).
  const int alongX = lessEqualMask(ay, ax) & lessEqualMask(az, ax);
  const int yBeatsZ = lessEqualMask(az, ay);
  const int alongY = ~alongX & yBeatsZ;
  const FN dominant = select(alongX, dx, select(alongY, dy, dz));
  // The components along (kz + 1) % 3 and (kz + 2) % 3; kx and ky are these, swapped where the
  // dominant component is negative.
  const FN next = select(alongX, dy, select(alongY, dz, dx));
  const FN afterNext = select(alongX, dz, select(alongY, dx, dy));
  const FN zero = FN::broadcast(0.f);
  const int negative = lessMask(dominant, zero);
  const FN alongKx = select(negative, afterNext, next), alongKy = select(negative, next, afterNext);
  // The axes as lanes of int bits (moved and blended, never computed with): kz, and the index of
  // (kx, ky) in kWatertightOtherAxes, kz * 2 + (dominant < 0). Written lane by lane, the axes took
  // 24 instructions a ray.
  const auto bits = [](int value) {
    float f;
    std::memcpy(&f, &value, sizeof f);
    return FN::broadcast(f);
  };
  const FN kz = select(alongX, bits(0), select(alongY, bits(1), bits(2)));
  const FN axisPair = select(alongX, select(negative, bits(1), bits(0)),
                             select(alongY, select(negative, bits(3), bits(2)), select(negative, bits(5), bits(4))));
  const FN fields[8] = {alongKx / dominant, alongKy / dominant, FN::broadcast(1.f) / dominant,
                        leading[0],         leading[1],         leading[2],
                        leading[3] * abs(dominant),
                        kz};
  for (int c = 0; c < 8; c += kLanes)
    FN::storeColumns(fields + c, reinterpret_cast<float*>(frames) + c, sizeof(WatertightRay) / sizeof(float));
  alignas(32) float pairBits[kLanes];
  axisPair.store(pairBits);
  for (; wanted; wanted &= wanted - 1) {
    const int lane = __builtin_ctz(wanted);
    int32_t pairIndex;
    std::memcpy(&pairIndex, &pairBits[lane], sizeof pairIndex);
    const WatertightAxisPair& pair = kWatertightOtherAxes[pairIndex];
    frames[lane].kx = pair.kx;
    frames[lane].ky = pair.ky;
  }
}

}  // namespace obvh
