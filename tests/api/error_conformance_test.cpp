// Misuse of the API must raise exactly the RTCError Embree raises. Each scenario runs the same
// calls on Debian's Embree and on obvh (both loaded side by side) and records the error code
// after every call, for the device and for the device-less (NULL) slot.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "crossval_harness.h"

namespace obvh::test {
namespace {

class Recorder {
 public:
  Recorder(const RtcLibrary& lib, RTCDevice device) : lib(lib), device(device) {}
  // Records the errors raised by the call just made.
  void check(const std::string& what) {
    log.push_back(what + " -> device " + std::to_string(lib.rtcGetDeviceError(device)) + ", null " +
                  std::to_string(lib.rtcGetDeviceError(nullptr)));
  }
  const RtcLibrary& lib;
  RTCDevice device;
  std::vector<std::string> log;
};

using Scenario = std::function<void(Recorder&)>;

// Runs the scenario on both libraries, each with a fresh device, and compares the logs line by line.
void expectSameErrors(const Scenario& scenario) {
  const LoadedLibraries& libs = libraries();
  std::vector<std::string> logs[2];
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  for (int k = 0; k < 2; ++k) {
    RTCDevice device = lib[k]->rtcNewDevice(k == 0 ? "isa=avx2" : nullptr);
    ASSERT_NE(device, nullptr);
    Recorder recorder(*lib[k], device);
    scenario(recorder);
    logs[k] = recorder.log;
    lib[k]->rtcReleaseDevice(device);
  }
  ASSERT_EQ(logs[0].size(), logs[1].size());
  ASSERT_FALSE(logs[0].empty());
  for (size_t i = 0; i < logs[0].size(); ++i) EXPECT_EQ(logs[0][i], logs[1][i]) << "embree vs obvh, step " << i;
}

RTCGeometry triangleWithBuffers(Recorder& r, float* vertices, unsigned* indices) {
  RTCGeometry g = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0, 12, 3);
  r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices, 0, 12, 1);
  return g;
}

TEST(ErrorConformance, NullHandles) {
  expectSameErrors([](Recorder& r) {
    r.lib.rtcNewScene(nullptr);
    r.check("rtcNewScene(NULL)");
    r.lib.rtcRetainScene(nullptr);
    r.check("rtcRetainScene(NULL)");
    r.lib.rtcReleaseScene(nullptr);
    r.check("rtcReleaseScene(NULL)");
    r.lib.rtcReleaseDevice(nullptr);
    r.check("rtcReleaseDevice(NULL)");
    r.lib.rtcCommitScene(nullptr);
    r.check("rtcCommitScene(NULL)");
    r.lib.rtcEnableGeometry(nullptr);
    r.check("rtcEnableGeometry(NULL)");
    r.lib.rtcCommitGeometry(nullptr);
    r.check("rtcCommitGeometry(NULL)");
    r.lib.rtcNewGeometry(nullptr, RTC_GEOMETRY_TYPE_TRIANGLE);
    r.check("rtcNewGeometry(NULL)");
    r.lib.rtcNewBuffer(nullptr, 16);
    r.check("rtcNewBuffer(NULL)");
    r.lib.rtcGetDeviceProperty(nullptr, RTC_DEVICE_PROPERTY_VERSION);
    r.check("rtcGetDeviceProperty(NULL)");
    r.lib.rtcSetDeviceProperty(nullptr, RTC_DEVICE_PROPERTY_VERSION, 0);
    r.check("rtcSetDeviceProperty(NULL, VERSION)");
    r.lib.rtcSetDeviceProperty(nullptr, RTCDeviceProperty(1000000), 0);
    r.check("rtcSetDeviceProperty(NULL, internal)");
  });
}

TEST(ErrorConformance, DeviceProperties) {
  expectSameErrors([](Recorder& r) {
    const RTCDeviceProperty readable[] = {RTC_DEVICE_PROPERTY_VERSION, RTC_DEVICE_PROPERTY_VERSION_MAJOR,
                                          RTC_DEVICE_PROPERTY_VERSION_MINOR, RTC_DEVICE_PROPERTY_VERSION_PATCH,
                                          RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED,
                                          RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED,
                                          RTC_DEVICE_PROPERTY_TRIANGLE_GEOMETRY_SUPPORTED,
                                          RTC_DEVICE_PROPERTY_QUAD_GEOMETRY_SUPPORTED,
                                          RTC_DEVICE_PROPERTY_TASKING_SYSTEM};
    for (RTCDeviceProperty p : readable) {
      const ssize_t value = r.lib.rtcGetDeviceProperty(r.device, p);
      r.check("property " + std::to_string(int(p)) + " = " + std::to_string(value));
    }
    r.lib.rtcGetDeviceProperty(r.device, RTCDeviceProperty(5));
    r.check("rtcGetDeviceProperty(unknown)");
    r.lib.rtcSetDeviceProperty(r.device, RTC_DEVICE_PROPERTY_VERSION, 0);
    r.check("rtcSetDeviceProperty(VERSION)");
    r.lib.rtcSetDeviceProperty(r.device, RTCDeviceProperty(1000000), 0);
    r.check("rtcSetDeviceProperty(internal)");
  });
}

TEST(ErrorConformance, FirstErrorSticksUntilRead) {
  expectSameErrors([](Recorder& r) {
    r.lib.rtcNewGeometry(r.device, RTCGeometryType(77));         // RTC_ERROR_UNKNOWN
    r.lib.rtcGetDeviceProperty(r.device, RTCDeviceProperty(5));  // RTC_ERROR_INVALID_ARGUMENT
    r.check("two errors, first is kept");
    r.check("read again: cleared");
  });
}

TEST(ErrorConformance, GeometryBufferMisuse) {
  expectSameErrors([](Recorder& r) {
    static float v[16] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static unsigned idx[8] = {0, 1, 2};
    RTCGeometry g = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    r.check("new triangle geometry");
    r.lib.rtcNewGeometry(r.device, RTCGeometryType(77));
    r.check("invalid geometry type");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_UINT3, v, 0, 12, 3);
    r.check("vertex buffer UINT3");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, v, 0, 16, 3);
    r.check("vertex buffer FLOAT4");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_FLOAT3, idx, 0, 12, 1);
    r.check("index buffer FLOAT3");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, idx, 0, 16, 1);
    r.check("triangle index buffer UINT4");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 1, RTC_FORMAT_UINT3, idx, 0, 12, 1);
    r.check("index buffer slot 1");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("vertex buffer slot 1");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("vertex attribute slot 0 without attribute count");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 10, 3);
    r.check("stride 10");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 2, 12, 3);
    r.check("offset 2");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("normal buffer on a triangle mesh");
    r.lib.rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, nullptr, 0, 12, 3);
    r.check("rtcSetGeometryBuffer(NULL buffer)");
    r.lib.rtcSetGeometryVertexAttributeCount(g, 1);
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("vertex attribute slot 0 with attribute count 1");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("valid vertex buffer");
    r.lib.rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0);
    r.check("update normal buffer");
    r.lib.rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 3);
    r.check("update vertex slot 3");
    const bool missing = r.lib.rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0) == nullptr;
    r.check(std::string("data of unset index buffer is null: ") + (missing ? "yes" : "no"));
    r.lib.rtcSetGeometryUserPrimitiveCount(g, 3);
    r.check("user primitive count on a triangle mesh");
    r.lib.rtcSetGeometryTimeStepCount(g, 200);
    r.check("200 time steps");
    r.lib.rtcSetGeometryTimeStepCount(g, 1);
    r.check("1 time step");
    r.lib.rtcSetGeometryBuildQuality(g, RTCBuildQuality(9));
    r.check("invalid geometry build quality");
    r.lib.rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_REFIT);
    r.check("geometry build quality REFIT");
    RTCGeometry q = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_QUAD);
    r.lib.rtcSetSharedGeometryBuffer(q, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, idx, 0, 12, 1);
    r.check("quad index buffer UINT3");
    r.lib.rtcSetNewGeometryBuffer(q, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 16, 4);
    r.check("new quad index buffer");
    r.lib.rtcReleaseGeometry(q);
    r.lib.rtcReleaseGeometry(g);
    r.check("release");
  });
}

// Grid meshes: a grid buffer instead of an index buffer, and the grid format for it alone.
TEST(ErrorConformance, GridBufferMisuse) {
  expectSameErrors([](Recorder& r) {
    static float v[16 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    static RTCGrid grid[2] = {{0, 2, 2, 2}, {0, 2, 2, 2}};
    static unsigned idx[8] = {0, 1, 2, 3};
    RTCGeometry g = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_GRID);
    r.check("new grid geometry");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, idx, 0, 16, 1);
    r.check("index buffer on a grid mesh");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_UINT4, grid, 0, 12, 1);
    r.check("grid buffer UINT4");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 1, RTC_FORMAT_GRID, grid, 0, 12, 1);
    r.check("grid buffer slot 1");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, grid, 2, 12, 1);
    r.check("grid buffer offset 2");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, v, 0, 16, 4);
    r.check("grid vertex buffer FLOAT4");
    const bool missing = r.lib.rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_GRID, 0) == nullptr;
    r.check(std::string("data of unset grid buffer is null: ") + (missing ? "yes" : "no"));
    r.lib.rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0);
    r.check("data of an index buffer on a grid mesh");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, grid, 0, 12, 2);
    r.check("valid grid buffer");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 4);
    r.check("valid grid vertex buffer");
    r.lib.rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0);
    r.check("update grid buffer");
    r.lib.rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 1);
    r.check("update grid buffer slot 1");
    r.lib.rtcCommitGeometry(g);
    r.check("commit grid geometry");
    RTCGeometry t = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    r.lib.rtcSetSharedGeometryBuffer(t, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, grid, 0, 12, 1);
    r.check("grid buffer on a triangle mesh");
    r.lib.rtcReleaseGeometry(t);
    r.lib.rtcReleaseGeometry(g);
    r.check("release");
  });
}

// Subdivision geometries: their own buffer types, formats and slots, topologies, modes, attribute
// topologies and the half-edge queries; and the same calls on a triangle mesh.
TEST(ErrorConformance, SubdivisionMisuse) {
  expectSameErrors([](Recorder& r) {
    static float v[8 * 3] = {-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, 1, -1, 1, 1, 1, -1, 1, 1};
    static unsigned idx[20] = {0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 0, 3, 7, 4, 4, 7, 6, 5};
    static unsigned faces[5] = {4, 4, 4, 4, 4};
    static float weights[4] = {1, 2, 3, 4};
    RTCGeometry g = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_SUBDIVISION);
    r.check("new subdivision geometry");
    const struct {
      RTCBufferType type;
      unsigned slot;
      RTCFormat format;
      const char* what;
    } bindings[] = {
        {RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_FLOAT, "face FLOAT"}, {RTC_BUFFER_TYPE_FACE, 1, RTC_FORMAT_UINT, "face slot 1"},
        {RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, "index UINT3"}, {RTC_BUFFER_TYPE_INDEX, 1, RTC_FORMAT_UINT, "index slot 1"},
        {RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, "vertex FLOAT4"},
        {RTC_BUFFER_TYPE_EDGE_CREASE_INDEX, 0, RTC_FORMAT_UINT, "edge crease index UINT"},
        {RTC_BUFFER_TYPE_EDGE_CREASE_INDEX, 1, RTC_FORMAT_UINT2, "edge crease index slot 1"},
        {RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT, 0, RTC_FORMAT_UINT, "edge crease weight UINT"},
        {RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX, 0, RTC_FORMAT_UINT2, "vertex crease index UINT2"},
        {RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT, 0, RTC_FORMAT_UINT, "vertex crease weight UINT"},
        {RTC_BUFFER_TYPE_HOLE, 0, RTC_FORMAT_FLOAT, "hole FLOAT"}, {RTC_BUFFER_TYPE_HOLE, 1, RTC_FORMAT_UINT, "hole slot 1"},
        {RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_UINT, "level UINT"}, {RTC_BUFFER_TYPE_LEVEL, 1, RTC_FORMAT_FLOAT, "level slot 1"},
        {RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, "grid buffer"}, {RTC_BUFFER_TYPE_FLAGS, 0, RTC_FORMAT_UCHAR, "flags buffer"},
        {RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, "attribute without a count"},
        {RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_FLOAT, "levels"}};
    for (const auto& b : bindings) {
      r.lib.rtcSetSharedGeometryBuffer(g, b.type, b.slot, b.format, weights, 0, 4, 4);
      r.check(b.what);
    }
    r.lib.rtcSetGeometryTopologyCount(g, 0);
    r.check("topology count 0");
    r.lib.rtcSetGeometryTopologyCount(g, 2);
    r.check("topology count 2");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 1, RTC_FORMAT_UINT, idx, 0, 4, 20);
    r.check("index slot 1 of two topologies");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 2, RTC_FORMAT_UINT, idx, 0, 4, 20);
    r.check("index slot 2 of two topologies");
    r.lib.rtcSetGeometrySubdivisionMode(g, 1, RTC_SUBDIVISION_MODE_PIN_CORNERS);
    r.check("mode of topology 1");
    r.lib.rtcSetGeometrySubdivisionMode(g, 2, RTC_SUBDIVISION_MODE_PIN_CORNERS);
    r.check("mode of topology 2");
    r.lib.rtcSetGeometryVertexAttributeCount(g, 2);
    r.lib.rtcSetGeometryVertexAttributeTopology(g, 1, 1);
    r.check("attribute 1 on topology 1");
    r.lib.rtcSetGeometryVertexAttributeTopology(g, 1, 2);
    r.check("attribute 1 on topology 2");
    r.lib.rtcSetGeometryVertexAttributeTopology(g, 5, 0);
    r.check("attribute 5");
    r.lib.rtcSetGeometryTessellationRate(g, 3.f);
    r.check("tessellation rate");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v, 0, 12, 8);
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, idx, 0, 4, 20);
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_UINT, faces, 0, 4, 5);
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_FLOAT, weights, 0, 0, 20);
    r.check("buffers of an open cube");
    r.lib.rtcCommitGeometry(g);
    r.check("commit");
    r.check("face 6: " + std::to_string(r.lib.rtcGetGeometryFirstHalfEdge(g, 6)));
    r.check("opposite of edge 0 in topology 3: " + std::to_string(r.lib.rtcGetGeometryOppositeHalfEdge(g, 3, 0)));
    r.check("opposite of boundary edge 3: " + std::to_string(r.lib.rtcGetGeometryOppositeHalfEdge(g, 0, 3)));
    RTCGeometry t = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    r.lib.rtcSetGeometryTessellationRate(t, 3.f);
    r.check("tessellation rate of a triangle mesh");
    r.lib.rtcSetGeometryTopologyCount(t, 2);
    r.check("topology count of a triangle mesh");
    r.lib.rtcSetGeometrySubdivisionMode(t, 0, RTC_SUBDIVISION_MODE_PIN_ALL);
    r.check("mode of a triangle mesh");
    r.lib.rtcSetGeometryVertexAttributeTopology(t, 0, 0);
    r.check("attribute topology of a triangle mesh");
    r.check("first half-edge of a triangle mesh: " + std::to_string(r.lib.rtcGetGeometryFirstHalfEdge(t, 0)));
    for (RTCBufferType type : {RTC_BUFFER_TYPE_FACE, RTC_BUFFER_TYPE_LEVEL, RTC_BUFFER_TYPE_HOLE}) {
      r.lib.rtcSetSharedGeometryBuffer(t, type, 0, RTC_FORMAT_UINT, idx, 0, 4, 4);
      r.check("subdivision buffer on a triangle mesh");
    }
    r.lib.rtcReleaseGeometry(t);
    r.lib.rtcReleaseGeometry(g);
    r.check("release");
  });
}

// Motion blur: time step counts, a vertex buffer per step of one stride, time ranges.
TEST(ErrorConformance, MotionBlurMisuse) {
  expectSameErrors([](Recorder& r) {
    static float v[4 * 8] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static unsigned idx[4] = {0, 1, 2};
    RTCGeometry g = r.lib.rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    r.lib.rtcSetGeometryTimeStepCount(g, 0);
    r.check("0 time steps");
    r.lib.rtcSetGeometryTimeStepCount(g, 129);
    r.check("129 time steps");
    r.lib.rtcSetGeometryTimeStepCount(g, 130);
    r.check("130 time steps");
    r.lib.rtcSetGeometryTimeStepCount(g, 3);
    r.check("3 time steps");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 3, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.check("vertex buffer slot 3 of 3 steps");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, idx, 0, 12, 1);
    for (unsigned step = 0; step < 3; ++step)
      r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT3, v, 0, step == 2 ? 16 : 12, 3);
    r.check("vertex buffers of 3 steps, the last of stride 16");
    r.lib.rtcCommitGeometry(g);
    r.check("commit with unequal strides");
    r.lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 2, RTC_FORMAT_FLOAT3, v, 0, 12, 3);
    r.lib.rtcCommitGeometry(g);
    r.check("commit with equal strides");
    r.lib.rtcSetGeometryTimeRange(g, 0.5f, 0.25f);
    r.check("time range 0.5 .. 0.25");
    r.lib.rtcSetGeometryTimeRange(g, -0.5f, 1.5f);
    r.check("time range -0.5 .. 1.5");
    r.lib.rtcReleaseGeometry(g);
    r.check("release");
  });
}

TEST(ErrorConformance, SceneMisuse) {
  expectSameErrors([](Recorder& r) {
    static float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static unsigned idx[3] = {0, 1, 2};
    RTCScene scene = r.lib.rtcNewScene(r.device);
    RTCBounds bounds;
    r.lib.rtcGetSceneBounds(scene, &bounds);
    r.check("bounds of a never committed scene");
    RTCGeometry g = triangleWithBuffers(r, v, idx);
    const unsigned id = r.lib.rtcAttachGeometry(scene, g);
    r.check("attach returns " + std::to_string(id));
    r.lib.rtcAttachGeometryByID(scene, g, 5);
    r.check("attach the same geometry again by ID 5");
    static float below[9] = {0, 0, -5, 1, 0, -5, 0, 1, -5};  // behind g, so the closest hit is unambiguous
    RTCGeometry g2 = triangleWithBuffers(r, below, idx);
    r.lib.rtcAttachGeometryByID(scene, g2, 0);
    r.check("attach by occupied ID");
    r.lib.rtcAttachGeometryByID(scene, g2, RTC_INVALID_GEOMETRY_ID);
    r.check("attach by RTC_INVALID_GEOMETRY_ID");
    const unsigned id2 = r.lib.rtcAttachGeometry(scene, g2);
    r.check("attach fills the lowest free ID: " + std::to_string(id2));
    r.lib.rtcDetachGeometry(scene, 3);
    r.check("detach an empty slot");
    r.lib.rtcDetachGeometry(scene, 5);
    r.check("detach ID 5");
    r.lib.rtcDetachGeometry(scene, 5);
    r.check("detach ID 5 again");
    r.lib.rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_REFIT);
    r.check("scene build quality REFIT");
    r.lib.rtcSetSceneBuildQuality(scene, RTCBuildQuality(9));
    r.check("scene build quality 9");
    r.lib.rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    r.check("scene build quality HIGH");
    r.lib.rtcCommitScene(scene);
    r.check("commit with uncommitted geometries");
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_z = 1.f, rh.ray.dir_z = -1.f, rh.ray.tfar = INFINITY, rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    r.lib.rtcIntersect1(scene, &context, &rh);
    r.check("intersect an uncommitted scene");
    r.lib.rtcCommitGeometry(g);
    r.lib.rtcCommitGeometry(g2);
    r.lib.rtcCommitScene(scene);
    r.check("commit after committing the geometries");
    rh.ray.org_x = 0.2f, rh.ray.org_y = 0.2f;
    r.lib.rtcIntersect1(scene, &context, &rh);
    r.check("intersect: geom " + std::to_string(rh.hit.geomID) + " prim " + std::to_string(rh.hit.primID) +
            " t " + std::to_string(rh.ray.tfar));
    r.lib.rtcSetGeometryMask(g, 2);
    r.lib.rtcCommitScene(scene);
    r.check("commit after changing a mask without committing the geometry");
    r.lib.rtcSetGeometryInstancedScene(g, scene);
    r.check("instanced scene on a triangle mesh");
    const float xfm[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    r.lib.rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    r.check("transform on a triangle mesh");
    const int flags = int(r.lib.rtcGetSceneFlags(scene));
    r.check("scene flags " + std::to_string(flags));
    r.lib.rtcReleaseGeometry(g);
    r.lib.rtcReleaseGeometry(g2);
    r.lib.rtcReleaseScene(scene);
    r.check("release");
  });
}

TEST(ErrorConformance, ErrorCallbackSeesEveryError) {
  expectSameErrors([](Recorder& r) {
    static std::vector<int> seen;
    seen.clear();
    r.lib.rtcSetDeviceErrorFunction(r.device, [](void*, RTCError code, const char*) { seen.push_back(int(code)); },
                                    nullptr);
    r.lib.rtcNewGeometry(r.device, RTCGeometryType(77));
    r.lib.rtcGetDeviceProperty(r.device, RTCDeviceProperty(5));
    r.lib.rtcSetDeviceErrorFunction(r.device, nullptr, nullptr);
    std::string codes;
    for (int c : seen) codes += std::to_string(c) + " ";
    r.check("callback saw: " + codes);
  });
}

}  // namespace
}  // namespace obvh::test
