// The device memory monitor's contract (Embree's manual): every allocation and release is reported
// once, so an application that sums the bytes it is told of (leaving out allocations it cancels
// before they happen) is back at zero when every object is released; a cancel before an
// allocation fails the call with RTC_ERROR_OUT_OF_MEMORY.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

namespace {

struct Ledger {
  std::atomic<long long> bytes{0};
  std::atomic<long long> refuseAbove{-1};  // cancel allocations larger than this (-1: never)
};

bool monitor(void* user, ssize_t bytes, bool post) {
  Ledger& ledger = *static_cast<Ledger*>(user);
  const bool cancel = bytes > 0 && ledger.refuseAbove >= 0 && bytes > ledger.refuseAbove;
  if (!cancel || post) ledger.bytes += bytes;
  return !cancel;
}

RTCScene quadScene(RTCDevice device) {
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 400));
  auto* q = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 16, 100));
  for (unsigned i = 0; i < 100; ++i) {
    const float x = float(i);
    const float corners[12] = {x, 0, 0, x + 1, 0, 0, x + 1, 1, 0, x, 1, 0};
    for (int k = 0; k < 12; ++k) v[12 * i + k] = corners[k];
    for (unsigned c = 0; c < 4; ++c) q[4 * i + c] = 4 * i + c;
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  return scene;
}

TEST(MemoryMonitor, ReportsBalanceToZeroOnceEverythingIsReleased) {
  Ledger ledger;
  RTCDevice device = rtcNewDevice("");
  rtcSetDeviceMemoryMonitorFunction(device, monitor, &ledger);
  for (int round = 0; round < 3; ++round) {
    RTCScene scene = quadScene(device);
    rtcCommitScene(scene);
    EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_NONE);
    EXPECT_GT(ledger.bytes.load(), 0);
    rtcCommitScene(scene);  // a recommit reports only what changed
    rtcReleaseScene(scene);
    EXPECT_EQ(ledger.bytes.load(), 0) << "round " << round;
  }
  rtcReleaseDevice(device);
}

TEST(MemoryMonitor, ACancelBeforeAnAllocationFailsTheCallAndIsNotCounted) {
  Ledger ledger;
  RTCDevice device = rtcNewDevice("");
  rtcSetDeviceMemoryMonitorFunction(device, monitor, &ledger);
  ledger.refuseAbove = 1000;
  EXPECT_EQ(rtcNewBuffer(device, 4096), nullptr);
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_OUT_OF_MEMORY);
  EXPECT_EQ(ledger.bytes.load(), 0);
  // A scene's build is reported after it happened: a cancel fails the commit, the bytes count, and
  // releasing the scene gives them back.
  ledger.refuseAbove = -1;
  RTCScene scene = quadScene(device);
  ledger.refuseAbove = 0;
  rtcCommitScene(scene);
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_OUT_OF_MEMORY);
  ledger.refuseAbove = -1;
  rtcReleaseScene(scene);
  EXPECT_EQ(ledger.bytes.load(), 0);
  rtcReleaseDevice(device);
}

// obvh's wide layouts hold only their wide tree once committed; a scene whose meshes are all of
// RTC_BUILD_QUALITY_REFIT also keeps what a later refit needs (the binary tree and a copy of the
// triangles), and gives it back when the meshes are no longer REFIT.
TEST(MemoryMonitor, RefitMeshesKeepWhatARefitNeedsAndOtherMeshesDoNot) {
  for (const char* config : {"accel=bvh4", "accel=bvh8"}) {
    Ledger ledger;
    RTCDevice device = rtcNewDevice(config);
    if (!device) continue;  // bvh8 needs AVX2
    rtcSetDeviceMemoryMonitorFunction(device, monitor, &ledger);
    RTCScene scene = quadScene(device);
    RTCGeometry quads = rtcGetGeometry(scene, 0);
    rtcCommitScene(scene);
    const long long released = ledger.bytes.load();
    rtcSetGeometryBuildQuality(quads, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(quads);
    rtcCommitScene(scene);
    const long long kept = ledger.bytes.load();
    // 200 triangles of 48 bytes at least, besides the binary nodes.
    EXPECT_GE(kept, released + 200 * 48) << config;
    auto* v = static_cast<float*>(rtcGetGeometryBufferData(quads, RTC_BUFFER_TYPE_VERTEX, 0));
    for (int i = 0; i < 400; ++i) v[3 * i + 2] = 0.1f * std::sin(float(i));
    rtcUpdateGeometryBuffer(quads, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(quads);
    rtcCommitScene(scene);  // refitted: it still keeps the refit's data
    EXPECT_GE(ledger.bytes.load(), released + 200 * 48) << config;
    rtcSetGeometryBuildQuality(quads, RTC_BUILD_QUALITY_MEDIUM);
    rtcCommitGeometry(quads);
    rtcCommitScene(scene);
    EXPECT_EQ(ledger.bytes.load(), released) << config;
    EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_NONE) << config;
    rtcReleaseScene(scene);
    EXPECT_EQ(ledger.bytes.load(), 0) << config;
    rtcReleaseDevice(device);
  }
}

}  // namespace
