// Subdivision geometries on obvh alone (so the sanitizer run covers the API path): a mesh with
// every face size, holes, creases, levels, two topologies and motion blur is committed, traced,
// interpolated and walked by half-edges; a mesh of broken faces and indices is skipped, not read.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace {

struct Device {
  RTCDevice device = rtcNewDevice("");
  ~Device() { rtcReleaseDevice(device); }
};

template <typename T>
void fill(RTCGeometry g, RTCBufferType type, unsigned slot, RTCFormat format, const std::vector<T>& data,
          size_t components) {
  void* p = rtcSetNewGeometryBuffer(g, type, slot, format, sizeof(T) * components, data.size() / components);
  std::memcpy(p, data.data(), data.size() * sizeof(T));
}

TEST(SubdivisionApi, EveryFeatureTracesAndInterpolates) {
  Device d;
  RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_SUBDIVISION);
  ASSERT_NE(g, nullptr);
  // A cube whose bottom is two triangles and whose top is a pentagon with an extra vertex.
  const std::vector<float> v = {-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, 1, -1, 1, 1, 1, -1, 1, 1, 0, 1, 1.5f};
  const std::vector<unsigned> idx = {0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 8, 7, 3, 0, 3, 7, 4, 4, 7, 8, 6, 5, 0, 1, 2, 0, 2, 3};
  const std::vector<unsigned> faces = {4, 4, 5, 4, 5, 3, 3};
  rtcSetGeometryTimeStepCount(g, 2);
  fill(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 3);
  std::vector<float> later = v;
  for (float& c : later) c *= 1.2f;
  fill(g, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT3, later, 3);
  fill(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, idx, 1);
  fill(g, RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_UINT, faces, 1);
  fill(g, RTC_BUFFER_TYPE_EDGE_CREASE_INDEX, 0, RTC_FORMAT_UINT2, std::vector<unsigned>{0, 1, 1, 2}, 2);
  fill(g, RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT, 0, RTC_FORMAT_FLOAT, std::vector<float>{2.5f, INFINITY}, 1);
  fill(g, RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX, 0, RTC_FORMAT_UINT, std::vector<unsigned>{6}, 1);
  fill(g, RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT, 0, RTC_FORMAT_FLOAT, std::vector<float>{0.5f}, 1);
  fill(g, RTC_BUFFER_TYPE_HOLE, 0, RTC_FORMAT_UINT, std::vector<unsigned>{3}, 1);
  std::vector<float> levels(idx.size());
  for (size_t i = 0; i < levels.size(); ++i) levels[i] = 1.f + float(i % 4);
  fill(g, RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_FLOAT, levels, 1);
  rtcSetGeometryTopologyCount(g, 2);
  fill(g, RTC_BUFFER_TYPE_INDEX, 1, RTC_FORMAT_UINT, idx, 1);
  rtcSetGeometrySubdivisionMode(g, 1, RTC_SUBDIVISION_MODE_PIN_BOUNDARY);
  rtcSetGeometryVertexAttributeCount(g, 1);
  fill(g, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT2, std::vector<float>(18, 0.5f), 2);
  rtcSetGeometryVertexAttributeTopology(g, 0, 1);
  rtcCommitGeometry(g);
  RTCScene scene = rtcNewScene(d.device);
  rtcAttachGeometry(scene, g);
  rtcCommitScene(scene);
  ASSERT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_NONE);

  int hits = 0;
  for (int i = 0; i < 64; ++i) {
    RTCRayHit rh{};
    rh.ray.org_x = -0.8f + 0.025f * float(i), rh.ray.org_y = 5.f, rh.ray.org_z = 0.1f;
    rh.ray.dir_y = -1.f, rh.ray.tfar = INFINITY, rh.ray.mask = 0xFFFFFFFFu, rh.ray.time = float(i % 8) / 7.f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcIntersect1(scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    ++hits;
    EXPECT_LT(rh.hit.primID, faces.size());
    EXPECT_NE(rh.hit.primID, 3u);  // the hole
    float P[3], dPdu[3], dPdv[3], uv[2];
    RTCInterpolateArguments args{};
    args.geometry = g, args.primID = rh.hit.primID, args.u = rh.hit.u, args.v = rh.hit.v;
    args.bufferType = RTC_BUFFER_TYPE_VERTEX, args.bufferSlot = 0, args.P = P, args.dPdu = dPdu, args.dPdv = dPdv;
    args.valueCount = 3;
    rtcInterpolate(&args);
    EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_NONE);
    EXPECT_TRUE(std::isfinite(P[0]) && std::isfinite(dPdu[1]) && std::isfinite(dPdv[2]));
    args.bufferType = RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, args.P = uv, args.dPdu = args.dPdv = nullptr, args.valueCount = 2;
    rtcInterpolate(&args);
    EXPECT_NEAR(uv[0], 0.5f, 1e-5f);  // a constant attribute stays constant
  }
  EXPECT_GT(hits, 32);

  EXPECT_EQ(rtcGetGeometryFirstHalfEdge(g, 2), 8u);
  for (unsigned h = 0; h < idx.size(); ++h) {
    EXPECT_EQ(rtcGetGeometryPreviousHalfEdge(g, rtcGetGeometryNextHalfEdge(g, h)), h);
    const unsigned o = rtcGetGeometryOppositeHalfEdge(g, 0, h);
    EXPECT_EQ(rtcGetGeometryOppositeHalfEdge(g, 0, o), h);
  }
  rtcGetGeometryNextHalfEdge(g, unsigned(idx.size()));
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  RTCInterpolateArguments bad{};
  float P[3];
  bad.geometry = g, bad.primID = 99, bad.bufferType = RTC_BUFFER_TYPE_VERTEX, bad.P = P, bad.valueCount = 3;
  rtcInterpolate(&bad);  // Debian's Embree asserts here
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_INVALID_ARGUMENT);
  rtcReleaseScene(scene);
  rtcReleaseGeometry(g);
}

TEST(SubdivisionApi, BrokenFacesAreSkipped) {
  Device d;
  RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_SUBDIVISION);
  fill(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, NAN}, 3);
  // Faces: too small, an index past the vertices, a NaN vertex, one of 0xFFFFFFFF vertices.
  fill(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, std::vector<unsigned>{0, 1, 0, 1, 9, 0, 1, 2, 3}, 1);
  fill(g, RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_UINT, std::vector<unsigned>{2, 3, 4, 0xFFFFFFFFu}, 1);
  rtcCommitGeometry(g);
  RTCScene scene = rtcNewScene(d.device);
  rtcAttachGeometry(scene, g);
  rtcCommitScene(scene);
  EXPECT_EQ(rtcGetDeviceError(d.device), RTC_ERROR_NONE);
  RTCBounds b;
  rtcGetSceneBounds(scene, &b);
  EXPECT_GT(b.lower_x, b.upper_x);  // nothing was built
  rtcReleaseScene(scene);
  rtcReleaseGeometry(g);
}

}  // namespace
