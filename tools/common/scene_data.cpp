#include "scene_data.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace obvh::tools {

namespace {

// The time relative to [start, end]: 0 and 1 at its ends, outside [0, 1] when not in it.
float localTime(float time, float start, float end) {
  return end > start ? (time - start) / (end - start) : (time == start ? 0.f : -1.f);
}

}  // namespace

bool MeshData::presentAt(float time) const {
  if (laterSteps.empty()) return true;
  const float local = localTime(time, timeStart, timeEnd);
  return local >= 0.f && local <= 1.f;
}

bool MeshData::vertexAt(uint64_t index, float time, float out[3]) const {
  if (laterSteps.empty()) {
    for (int k = 0; k < 3; ++k) out[k] = vertices[3 * index + k];
    return true;
  }
  if (!presentAt(time)) return false;
  const float local = localTime(time, timeStart, timeEnd);
  const int segments = int(laterSteps.size());
  const float ftime = local * float(segments);
  const int segment = std::clamp(int(std::floor(ftime)), 0, segments - 1);
  const float f = ftime - float(segment);
  const std::vector<float>& a = segment == 0 ? vertices : laterSteps[segment - 1];
  const std::vector<float>& b = laterSteps[segment];
  for (int k = 0; k < 3; ++k) out[k] = a[3 * index + k] * (1.f - f) + b[3 * index + k] * f;
  return true;
}

size_t SceneData::primitiveCount() const {
  size_t n = 0;
  for (const MeshData& m : meshes) n += m.primitiveCount();
  return n;
}

CommittedScene::CommittedScene(const RtcLibrary& lib, RTCDevice device, const SceneData& data, RTCSceneFlags flags,
                               RTCBuildQuality quality)
    : lib_(lib) {
  scene_ = lib.rtcNewScene(device);
  if (!scene_) throw std::runtime_error(lib.label + ": rtcNewScene failed");
  lib.rtcSetSceneFlags(scene_, flags);
  lib.rtcSetSceneBuildQuality(scene_, quality);
  for (const MeshData& mesh : data.meshes) {
    const RTCGeometryType type =
        mesh.grid ? RTC_GEOMETRY_TYPE_GRID : mesh.quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE;
    RTCGeometry g = lib.rtcNewGeometry(device, type);
    if (!g) throw std::runtime_error(lib.label + ": rtcNewGeometry failed");
    if (!mesh.laterSteps.empty()) {
      lib.rtcSetGeometryTimeStepCount(g, mesh.timeStepCount());
      if (mesh.timeStart != 0.f || mesh.timeEnd != 1.f) lib.rtcSetGeometryTimeRange(g, mesh.timeStart, mesh.timeEnd);
      for (unsigned step = 1; step < mesh.timeStepCount(); ++step) {
        auto* later = static_cast<float*>(lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT3,
                                                                      3 * sizeof(float), mesh.vertexCount()));
        if (!later) throw std::runtime_error(lib.label + ": rtcSetNewGeometryBuffer failed");
        std::memcpy(later, mesh.laterSteps[step - 1].data(), mesh.vertices.size() * sizeof(float));
      }
    }
    // Library-owned buffers: both libraries get their own copy, so neither sees the other's data.
    auto* v = static_cast<float*>(lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), mesh.vertexCount()));
    void* primitives =
        mesh.grid ? lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid),
                                                mesh.primitiveCount())
                  : lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                mesh.quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                                (mesh.quads ? 4 : 3) * sizeof(uint32_t), mesh.primitiveCount());
    if (!v || (!primitives && mesh.primitiveCount() > 0))
      throw std::runtime_error(lib.label + ": rtcSetNewGeometryBuffer failed");
    std::memcpy(v, mesh.vertices.data(), mesh.vertices.size() * sizeof(float));
    if (mesh.grid)
      std::memcpy(primitives, mesh.grids.data(), mesh.grids.size() * sizeof(RTCGrid));
    else
      std::memcpy(primitives, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
    lib.rtcSetGeometryMask(g, mesh.mask);
    if (!mesh.enabled) lib.rtcDisableGeometry(g);
    lib.rtcCommitGeometry(g);
    lib.rtcAttachGeometry(scene_, g);
    geometries_.push_back(g);
  }
  lib.rtcCommitScene(scene_);
}

void CommittedScene::recommit(const SceneData& data) {
  for (size_t id = 0; id < geometries_.size(); ++id) {
    const MeshData& mesh = data.meshes.at(id);
    RTCGeometry g = geometries_[id];
    auto* v = static_cast<float*>(lib_.rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0));
    std::memcpy(v, mesh.vertices.data(), mesh.vertices.size() * sizeof(float));
    lib_.rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
    lib_.rtcSetGeometryMask(g, mesh.mask);
    if (mesh.enabled) lib_.rtcEnableGeometry(g); else lib_.rtcDisableGeometry(g);
    lib_.rtcCommitGeometry(g);
  }
  lib_.rtcCommitScene(scene_);
}

CommittedScene::~CommittedScene() {
  for (RTCGeometry g : geometries_) lib_.rtcReleaseGeometry(g);
  if (scene_) lib_.rtcReleaseScene(scene_);
}

HitRecord toHitRecord(const RTCRayHit& rayhit) {
  HitRecord h;
  h.geomID = rayhit.hit.geomID;
  if (!h.hit()) return h;
  h.primID = rayhit.hit.primID;
  h.t = rayhit.ray.tfar;
  h.u = rayhit.hit.u;
  h.v = rayhit.hit.v;
  h.Ng[0] = rayhit.hit.Ng_x;
  h.Ng[1] = rayhit.hit.Ng_y;
  h.Ng[2] = rayhit.hit.Ng_z;
  return h;
}

}  // namespace obvh::tools
