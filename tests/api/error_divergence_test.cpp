// Misuse where Debian's Embree crashes, asserts or reads out of bounds: obvh reports an error
// instead. Also obvh's own configuration errors. Runs on obvh alone, through obvh's header.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

struct Device {
  RTCDevice device = rtcNewDevice(nullptr);
  ~Device() { rtcReleaseDevice(device); }
};

TEST(ErrorDivergence, QueriesWithNullHandlesReportInvalidArgument) {
  Device d;
  RTCScene scene = rtcNewScene(d.device);
  rtcCommitScene(scene);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rtcIntersect1(nullptr, &context, &rh);  // Embree 3.13.5 segfaults here
  EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT);
  rtcOccluded1(nullptr, &context, &rh.ray);
  EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT);
  rtcIntersect1(scene, nullptr, &rh);
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  rtcIntersect1(scene, &context, nullptr);
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  rtcReleaseScene(scene);
}

TEST(ErrorDivergence, GetGeometryPastTheEndReportsInvalidArgument) {
  Device d;
  RTCScene scene = rtcNewScene(d.device);
  EXPECT_EQ(rtcGetGeometry(scene, 5), nullptr);  // Embree 3.13.5 asserts here
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  rtcReleaseScene(scene);
}

TEST(ErrorDivergence, BufferRangeLargerThanTheBufferIsRejected) {
  Device d;
  RTCBuffer buffer = rtcNewBuffer(d.device, 16);
  RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, buffer, 0, 12, 3);  // needs 36 bytes
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, buffer, 4, 12, 1);  // 16 bytes: fits
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_NONE);
  rtcReleaseGeometry(g);
  rtcReleaseBuffer(buffer);
}

// Debian's Embree aborts (assertion) when it builds a grid of one row or column or with a vertex
// past the buffer, and reads past the grid when it interpolates one: obvh skips such grids when it
// builds and refuses to interpolate them.
TEST(ErrorDivergence, GridsWithoutCellsAreSkippedAndNotInterpolated) {
  Device d;
  static float v[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  static RTCGrid grids[3] = {{0, 2, 1, 2}, {0, 2, 2, 1}, {2, 2, 2, 2}};  // a column, a row, past the end
  RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_GRID);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 4);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, grids, 0, sizeof(RTCGrid), 3);
  rtcCommitGeometry(g);
  RTCScene scene = rtcNewScene(d.device);
  rtcAttachGeometry(scene, g);
  rtcCommitScene(scene);
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_NONE);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = 0.25f, rh.ray.org_y = 0.25f, rh.ray.org_z = 1.f, rh.ray.dir_z = -1.f;
  rh.ray.tfar = INFINITY, rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  for (unsigned prim : {0u, 1u}) {
    float P[3];
    RTCInterpolateArguments args{g, prim, 0.5f, 0.5f, RTC_BUFFER_TYPE_VERTEX, 0, P, nullptr, nullptr,
                                 nullptr, nullptr, nullptr, 3};
    rtcInterpolate(&args);
    EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT) << "grid " << prim;
  }
  rtcReleaseScene(scene);
  rtcReleaseGeometry(g);
}

TEST(ErrorDivergence, UnimplementedFeaturesFailLoudly) {
  Device d;
  std::vector<std::string> messages;
  rtcSetDeviceErrorFunction(
      d.device, [](void* user, RTCError, const char* msg) { static_cast<std::vector<std::string>*>(user)->push_back(msg); },
      &messages);
  for (RTCGeometryType type : {RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE,
                               RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_HERMITE_CURVE, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE,
                               RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT, RTC_GEOMETRY_TYPE_DISC_POINT}) {
    EXPECT_EQ(rtcNewGeometry(d.device, type), nullptr);
    EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_OPERATION);
  }
  // Subdivision surfaces without displacement (Embree has it).
  RTCGeometry subdivision = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_SUBDIVISION);
  ASSERT_NE(subdivision, nullptr);
  rtcSetGeometryDisplacementFunction(subdivision, [](const RTCDisplacementFunctionNArguments*) {});
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_OPERATION);
  rtcReleaseGeometry(subdivision);
  RTCScene scene = rtcNewScene(d.device);
  EXPECT_EQ(rtcNewBVH(d.device), nullptr);
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_CURVE_GEOMETRY_SUPPORTED), 0);
  EXPECT_EQ(rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_SUBDIVISION_GEOMETRY_SUPPORTED), 1);
  EXPECT_EQ(rtcGetDeviceProperty(d.device, RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED), 0);
  for (const std::string& m : messages) EXPECT_FALSE(m.empty());
  EXPECT_GE(messages.size(), 6u);
  rtcReleaseScene(scene);
}

TEST(DeviceConfig, EmbreeTokensAndUnknownNamesAreAccepted) {
  for (const char* config : {"", "threads=1", "verbose=0,isa=avx2", "accel=bvh4.triangle4", "foo=bar",
                             "accel=bvh2,intersector=watertight,build_bins=16,max_leaf_size=2", "accel=bvh4",
                             "intersector=fast", "ray_mask=off", "accel=obb", "accel=hybrid,obb_split=median",
                             "accel=obb,obb_split=midpoint,obb_bins=100,obb_clusters=1000,obb_cost=15",
                             "accel=hybrid,obb_split=aabb", "builder=kmeans,kmeans_k=4", "builder=sah",
                             "builder=distance,distance_alpha=0.25,distance_source=1.5:-2:3e2",
                             "traversal_cost=2.5,intersection_cost=0.5", "collapse=greedy", "collapse=sah,accel=bvh4",
                             "collapse=default", "accel=obb,obb_palette=7", "accel=hybrid,obb_palette=1,obb_width=4",
                             "child_order=fixed", "child_order=near_to_far", "child_order=default,accel=bvh4",
                             "accel=obb,obb_packets=on", "obb_packets=off", "obb_packets=default",
                             "accel=obb,obb_fit=pca", "accel=hybrid,obb_fit=dito14", "obb_fit=default"}) {
    RTCDevice device = rtcNewDevice(config);
    EXPECT_NE(device, nullptr) << config;
    EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_NONE) << config;
    rtcReleaseDevice(device);
  }
}

TEST(DeviceConfig, ValuesObvhCannotHonourAreRejected) {
  for (const char* config : {"threads=-1", "accel=bvh16", "accel=nonsense", "intersector=foo",
                             "build_bins=1", "max_leaf_size=x", "ray_mask=maybe", "obb_split=best", "obb_bins=1",
                             "obb_clusters=-1", "obb_palette=8", "obb_palette=-1", "obb_palette=x", "obb_cost=0", "builder=octree", "kmeans_k=9", "kmeans_k=1",
                             "distance_alpha=1.5", "distance_alpha=x", "distance_source=1:2", "distance_source=1:2:3:4",
                             "distance_source=a:b:c", "traversal_cost=0", "intersection_cost=-1",
                             "collapse=optimal", "child_order=sorted", "obb_packets=yes", "obb_fit=pca2",
                             "obb_fit="}) {
    EXPECT_EQ(rtcNewDevice(config), nullptr) << config;
    EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT) << config;
  }
}

TEST(DeviceConfig, ObvhConfigEnvironmentVariableApplies) {
  setenv("OBVH_CONFIG", "accel=nonsense", 1);
  EXPECT_EQ(rtcNewDevice("threads=1"), nullptr);
  EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT);
  setenv("OBVH_CONFIG", "build_bins=8", 1);
  RTCDevice device = rtcNewDevice("threads=1");
  EXPECT_NE(device, nullptr);
  rtcReleaseDevice(device);
  unsetenv("OBVH_CONFIG");
}

TEST(RefCounts, ObjectsStayAliveWhileReferenced) {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 3));
  unsigned* i = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, 1));
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int k = 0; k < 9; ++k) v[k] = tri[k];
  i[0] = 0, i[1] = 1, i[2] = 2;
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);    // the scene still holds it
  rtcReleaseDevice(device); // the scene still holds the device
  rtcCommitScene(scene);
  RTCDevice same = rtcGetSceneDevice(scene);
  EXPECT_EQ(same, device);
  EXPECT_EQ(rtcGetGeometry(scene, 0), g);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = 0.25f, rh.ray.org_y = 0.25f, rh.ray.org_z = -1.f, rh.ray.dir_z = 1.f;
  rh.ray.tfar = INFINITY, rh.ray.mask = ~0u, rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  EXPECT_EQ(rh.hit.geomID, 0u);
  EXPECT_FLOAT_EQ(rh.ray.tfar, 1.f);
  EXPECT_EQ(rtcGetDeviceError(same), RTC_ERROR_NONE);
  rtcReleaseScene(scene);
  rtcReleaseDevice(same);
}

}  // namespace

namespace {

// Traces one ray with the given mask against a triangle whose geometry mask is geometryMask.
bool hitsWithMasks(const char* config, unsigned geometryMask, unsigned rayMask, ssize_t* maskProperty) {
  RTCDevice device = rtcNewDevice(config);
  *maskProperty = rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED);
  RTCScene scene = rtcNewScene(device);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  static const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  static const unsigned idx[3] = {0, 1, 2};
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
  rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, idx, 0, 12, 1);
  rtcSetGeometryMask(g, geometryMask);
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = 0.2f, rh.ray.org_y = 0.2f, rh.ray.org_z = 1.f, rh.ray.dir_z = -1.f;
  rh.ray.tfar = INFINITY, rh.ray.mask = rayMask, rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return rh.hit.geomID == 0;
}

TEST(DeviceConfig, RayMaskOffIgnoresMasks) {
  ssize_t property = -1;
  EXPECT_FALSE(hitsWithMasks("ray_mask=on", 0xFFFFFFFFu, 0u, &property));  // Embree's default: mask 0 hits nothing
  EXPECT_EQ(property, 1);
  EXPECT_FALSE(hitsWithMasks(nullptr, 0x2u, 0x1u, &property));
  EXPECT_TRUE(hitsWithMasks("ray_mask=off", 0xFFFFFFFFu, 0u, &property));
  EXPECT_EQ(property, 0);
  EXPECT_TRUE(hitsWithMasks("ray_mask=off", 0x2u, 0x1u, &property));
}

}  // namespace
