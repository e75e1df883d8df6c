// rtcIntersect1 / rtcOccluded1 and the packet queries take a short path straight to the triangle
// kernels when a scene is one wide triangle tree with nothing to call back. These tests pin down
// when it must not be taken (while traversal steps are counted, with a context filter, before a
// commit) and that it answers in every wide layout.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>
#include <obvh/traversal_statistics.h>

#include <cmath>
#include <limits>

namespace {

class SingleRayPath : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    device = rtcNewDevice(GetParam());
    ASSERT_NE(device, nullptr);
    scene = rtcNewScene(device);
    // Enough triangles for a tree of several nodes: a row of unit squares in the z = 0 plane.
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    constexpr unsigned kSquares = 64;
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * kSquares));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2 * kSquares));
    for (unsigned s = 0; s < kSquares; ++s) {
      const float corners[4][3] = {{float(s), 0, 0}, {float(s) + 1, 0, 0}, {float(s) + 1, 1, 0}, {float(s), 1, 0}};
      for (int c = 0; c < 4; ++c)
        for (int axis = 0; axis < 3; ++axis) vertices[(4 * s + c) * 3 + axis] = corners[c][axis];
      const unsigned quad[6] = {4 * s, 4 * s + 1, 4 * s + 2, 4 * s, 4 * s + 2, 4 * s + 3};
      for (int k = 0; k < 6; ++k) indices[6 * s + k] = quad[k];
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  void TearDown() override {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }

  // A ray straight down onto square 10.
  static RTCRayHit rayDown() {
    RTCRayHit rayhit{};
    rayhit.ray.org_x = 10.3f, rayhit.ray.org_y = 0.4f, rayhit.ray.org_z = 5.f;
    rayhit.ray.dir_z = -1.f;
    rayhit.ray.tfar = std::numeric_limits<float>::infinity();
    rayhit.ray.mask = 0xFFFFFFFFu;
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return rayhit;
  }

  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
};

TEST_P(SingleRayPath, TraversalStatisticsCountSingleRays) {
  rtcCommitScene(scene);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  obvhEnableTraversalStatistics(1);
  RTCRayHit rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  EXPECT_EQ(rayhit.hit.primID, 21u);  // the upper-left half of square 10
  ObvhTraversalStatistics counted{};
  obvhTakeTraversalStatistics(&counted);
  EXPECT_GT(counted.boundingVolumeTests, 0u);
  EXPECT_GT(counted.leafVisits, 0u);

  RTCRay shadow = rayDown().ray;
  rtcOccluded1(scene, &context, &shadow);
  EXPECT_EQ(shadow.tfar, -std::numeric_limits<float>::infinity());
  obvhTakeTraversalStatistics(&counted);
  EXPECT_GT(counted.leafVisits, 0u);

  obvhEnableTraversalStatistics(0);
  rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  obvhTakeTraversalStatistics(&counted);
  EXPECT_EQ(counted.boundingVolumeTests, 0u);
  EXPECT_EQ(counted.leafVisits, 0u);
}

// Rejects every hit and counts its calls.
void rejectAll(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) args->valid[i] = 0;
  ++*static_cast<int*>(args->geometryUserPtr);
}

int contextFilterCalls = 0;
void rejectAllInContext(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i) args->valid[i] = 0;
  ++contextFilterCalls;
}

TEST_P(SingleRayPath, ContextFilterRunsWhenTheSceneAsksForIt) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.filter = rejectAllInContext;

  rtcCommitScene(scene);
  contextFilterCalls = 0;
  RTCRayHit rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  EXPECT_EQ(rayhit.hit.geomID, 0u) << "without RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION the context filter is ignored";
  EXPECT_EQ(contextFilterCalls, 0);

  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcCommitScene(scene);
  rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  EXPECT_EQ(rayhit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_GT(contextFilterCalls, 0);

  const int intersectCalls = contextFilterCalls;
  RTCRay shadow = rayDown().ray;
  rtcOccluded1(scene, &context, &shadow);
  EXPECT_EQ(shadow.tfar, std::numeric_limits<float>::infinity());
  EXPECT_GT(contextFilterCalls, intersectCalls);
}

TEST_P(SingleRayPath, GeometryFilterRuns) {
  int calls = 0;
  RTCGeometry geometry = rtcGetGeometry(scene, 0);
  rtcSetGeometryUserData(geometry, &calls);
  rtcSetGeometryIntersectFilterFunction(geometry, rejectAll);
  rtcCommitGeometry(geometry);
  rtcCommitScene(scene);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  EXPECT_EQ(rayhit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_GT(calls, 0);
}

TEST_P(SingleRayPath, ModifiedSceneIsNotTracedUntilCommitted) {
  rtcCommitScene(scene);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // marks the scene modified
  rtcGetDeviceError(device);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit = rayDown();
  rtcIntersect1(scene, &context, &rayhit);
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(rayhit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  RTCRay shadow = rayDown().ray;
  rtcOccluded1(scene, &context, &shadow);
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(shadow.tfar, std::numeric_limits<float>::infinity());
}

// The short path's kernels are chosen at commit (the layout's, for incoherent and for coherent
// rays): each answers as the general path does, with every field of the hit, and a scene without
// triangles misses.
TEST_P(SingleRayPath, BothWalksAnswerAndAnEmptySceneMisses) {
  rtcCommitScene(scene);
  for (const RTCIntersectContextFlags flags : {RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT, RTC_INTERSECT_CONTEXT_FLAG_COHERENT}) {
    SCOPED_TRACE(flags);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = flags;
    RTCRayHit rayhit = rayDown();
    rayhit.hit.instID[0] = 7u;  // overwritten by a hit outside instances
    rtcIntersect1(scene, &context, &rayhit);
    EXPECT_EQ(rayhit.ray.tfar, 5.f);
    EXPECT_EQ(rayhit.hit.geomID, 0u);
    EXPECT_EQ(rayhit.hit.primID, 21u);  // the upper-left half of square 10: corners (10,0) (11,1) (10,1)
    EXPECT_EQ(rayhit.hit.instID[0], RTC_INVALID_GEOMETRY_ID);
    // Embree's Ng = (v2 - v0) x (v0 - v1) = (0, 1, 0) x (-1, -1, 0).
    EXPECT_EQ(rayhit.hit.Ng_x, 0.f);
    EXPECT_EQ(rayhit.hit.Ng_y, 0.f);
    EXPECT_EQ(rayhit.hit.Ng_z, 1.f);
    EXPECT_NEAR(rayhit.hit.u, 0.3f, 1e-6f);
    EXPECT_NEAR(rayhit.hit.v, 0.1f, 1e-6f);
    RTCRay shadow = rayDown().ray;
    rtcOccluded1(scene, &context, &shadow);
    EXPECT_EQ(shadow.tfar, -std::numeric_limits<float>::infinity());
    RTCRay past = rayDown().ray;
    past.org_x = 70.f;  // beyond the row of squares
    rtcOccluded1(scene, &context, &past);
    EXPECT_EQ(past.tfar, std::numeric_limits<float>::infinity());
  }

  RTCScene empty = rtcNewScene(device);
  rtcCommitScene(empty);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit = rayDown();
  rtcIntersect1(empty, &context, &rayhit);
  EXPECT_EQ(rayhit.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(rayhit.ray.tfar, std::numeric_limits<float>::infinity());
  RTCRay shadow = rayDown().ray;
  rtcOccluded1(empty, &context, &shadow);
  EXPECT_EQ(shadow.tfar, std::numeric_limits<float>::infinity());
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_NONE);
  rtcReleaseScene(empty);
}

// Packets take the same short path: lanes follow the valid mask, hits are written whole.
TEST_P(SingleRayPath, PacketsAnswerLaneByLane) {
  rtcCommitScene(scene);
  RTCScene empty = rtcNewScene(device);
  rtcCommitScene(empty);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  constexpr int kLanes = 8;
  const int valid[kLanes] = {-1, 0, -1, -1, 0, -1, -1, -1};
  RTCRayHit8 packet{};
  RTCRay8 shadows{};
  for (int lane = 0; lane < kLanes; ++lane) {
    const RTCRayHit one = rayDown();
    // Lane k looks down onto square 2k + 1, lane 7 past the end of the row.
    const float x = lane == 7 ? 70.f : 2.f * float(lane) + 1.3f;
    packet.ray.org_x[lane] = shadows.org_x[lane] = x;
    packet.ray.org_y[lane] = shadows.org_y[lane] = one.ray.org_y;
    packet.ray.org_z[lane] = shadows.org_z[lane] = one.ray.org_z;
    packet.ray.dir_z[lane] = shadows.dir_z[lane] = one.ray.dir_z;
    packet.ray.tfar[lane] = shadows.tfar[lane] = one.ray.tfar;
    packet.ray.mask[lane] = shadows.mask[lane] = one.ray.mask;
    packet.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCRayHit8 inEmpty = packet;
  RTCRay8 shadowsInEmpty = shadows;
  rtcIntersect8(valid, scene, &context, &packet);
  rtcOccluded8(valid, scene, &context, &shadows);
  rtcIntersect8(valid, empty, &context, &inEmpty);
  rtcOccluded8(valid, empty, &context, &shadowsInEmpty);
  EXPECT_EQ(rtcGetDeviceError(device), RTC_ERROR_NONE);
  const float infinity = std::numeric_limits<float>::infinity();
  for (int lane = 0; lane < kLanes; ++lane) {
    SCOPED_TRACE(lane);
    const bool hits = valid[lane] == -1 && lane != 7;
    EXPECT_EQ(packet.hit.geomID[lane], hits ? 0u : RTC_INVALID_GEOMETRY_ID);
    EXPECT_EQ(packet.ray.tfar[lane], hits ? 5.f : infinity);
    EXPECT_EQ(shadows.tfar[lane], hits ? -infinity : infinity);
    EXPECT_EQ(inEmpty.hit.geomID[lane], RTC_INVALID_GEOMETRY_ID);
    EXPECT_EQ(shadowsInEmpty.tfar[lane], infinity);
    if (!hits) continue;
    EXPECT_EQ(packet.hit.primID[lane], 4u * unsigned(lane) + 3u);  // the upper-left half of square 2k + 1
    EXPECT_EQ(packet.hit.instID[0][lane], RTC_INVALID_GEOMETRY_ID);
    EXPECT_EQ(packet.hit.Ng_z[lane], 1.f);
    EXPECT_NEAR(packet.hit.u[lane], 0.3f, 1e-6f);
    EXPECT_NEAR(packet.hit.v[lane], 0.1f, 1e-6f);
  }
  rtcReleaseScene(empty);
}

INSTANTIATE_TEST_SUITE_P(WideLayouts, SingleRayPath,
                         ::testing::Values("accel=bvh8", "accel=bvh4", "accel=obb,obb_width=4",
                                           "accel=hybrid,obb_width=4"));

}  // namespace
