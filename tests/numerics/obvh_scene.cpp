#include "obvh_scene.h"

#include <gtest/gtest.h>

namespace obvh::test {

const ObvhMode kEveryMode[11] = {{"watertight", nullptr, RTC_SCENE_FLAG_NONE},
                                {"robust_flag", nullptr, RTC_SCENE_FLAG_ROBUST},
                                {"fast", "intersector=fast", RTC_SCENE_FLAG_NONE},
                                {"bvh2", "accel=bvh2", RTC_SCENE_FLAG_NONE},
                                {"bvh4", "accel=bvh4", RTC_SCENE_FLAG_NONE},
                                {"obb", "accel=obb", RTC_SCENE_FLAG_NONE},
                                {"hybrid", "accel=hybrid", RTC_SCENE_FLAG_NONE},
                                {"obb_clusters", "accel=obb,obb_clusters=32", RTC_SCENE_FLAG_NONE},
                                {"obb_own_frames", "accel=obb,obb_palette=0", RTC_SCENE_FLAG_NONE},
                                {"obb_binary", "accel=obb,obb_width=2", RTC_SCENE_FLAG_NONE},
                                {"obb_four_wide", "accel=obb,obb_width=4", RTC_SCENE_FLAG_NONE}};
const ObvhMode kWatertightModes[10] = {kEveryMode[0], kEveryMode[1], kEveryMode[3], kEveryMode[4], kEveryMode[5],
                                       kEveryMode[6], kEveryMode[7], kEveryMode[8], kEveryMode[9], kEveryMode[10]};

std::string modeName(const ::testing::TestParamInfo<ObvhMode>& info) { return info.param.name; }
void PrintTo(const ObvhMode& mode, std::ostream* os) { *os << mode.name; }

ObvhScene::ObvhScene(const std::vector<MeshData>& meshes, const char* config, RTCSceneFlags flags)
    : device_(rtcNewDevice(config)), scene_(rtcNewScene(device_)), meshes_(meshes) {
  rtcSetSceneFlags(scene_, flags);
  for (const MeshData& mesh : meshes_) {
    RTCGeometry g = rtcNewGeometry(device_, mesh.quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.vertices.data(), 0, 12,
                               mesh.vertexCount());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, mesh.quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                               mesh.indices.data(), 0, mesh.quads ? 16 : 12, mesh.primitiveCount());
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(scene_);
  EXPECT_EQ(rtcGetDeviceError(device_), RTC_ERROR_NONE);
}

ObvhScene::~ObvhScene() {
  rtcReleaseScene(scene_);
  rtcReleaseDevice(device_);
}

RTCRayHit ObvhScene::intersect(const RTCRay& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray = ray;
  rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  return rh;
}

bool ObvhScene::occluded(const RTCRay& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay r = ray;
  rtcOccluded1(scene_, &context, &r);
  return r.tfar == -kInf;
}

RTCRay makeRay(const float org[3], const float dir[3], float tnear, float tfar) {
  RTCRay r{};
  r.org_x = org[0], r.org_y = org[1], r.org_z = org[2];
  r.dir_x = dir[0], r.dir_y = dir[1], r.dir_z = dir[2];
  r.tnear = tnear;
  r.tfar = tfar;
  r.mask = 0xFFFFFFFFu;
  return r;
}

}  // namespace obvh::test
