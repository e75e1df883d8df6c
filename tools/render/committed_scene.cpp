#include "committed_scene.h"

#include <cstring>
#include <stdexcept>

namespace obvh::render {
namespace {

RTCGeometry newTriangles(const tools::RtcLibrary& lib, RTCDevice device, const Primitive& p, RTCBuildQuality quality) {
  RTCGeometry g = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (!g) throw std::runtime_error(lib.label + ": rtcNewGeometry failed");
  auto* vertices = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p.vertexCount());
  auto* indices = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), p.triangleCount());
  if (!vertices || !indices) throw std::runtime_error(lib.label + ": rtcSetNewGeometryBuffer failed");
  std::memcpy(indices, p.indices.data(), p.indices.size() * sizeof(uint32_t));
  lib.rtcSetGeometryBuildQuality(g, quality);
  return g;
}

}  // namespace

CommittedRenderScene::CommittedRenderScene(const tools::RtcLibrary& lib, RTCDevice device, const RenderScene& scene,
                                           const ScenePose& pose, bool animated, RTCBuildQuality quality)
    : lib_(lib), scene_(scene) {
  std::vector<int> placements(scene.meshes.size(), 0);
  for (const PlacedMesh& placed : pose.meshes) ++placements[size_t(placed.mesh)];
  const RTCBuildQuality geometryQuality = animated ? RTC_BUILD_QUALITY_REFIT : RTC_BUILD_QUALITY_MEDIUM;

  // Meshes used more than once become prototype scenes, built once.
  prototypes_.assign(scene.meshes.size(), nullptr);
  prototypePrimitive_.resize(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (placements[m] < 2) continue;
    RTCScene prototype = lib.rtcNewScene(device);
    lib.rtcSetSceneBuildQuality(prototype, quality);
    for (size_t p = 0; p < scene.meshes[m].primitives.size(); ++p) {
      const Primitive& primitive = scene.meshes[m].primitives[p];
      if (primitive.triangleCount() == 0) continue;
      RTCGeometry g = newTriangles(lib, device, primitive, RTC_BUILD_QUALITY_MEDIUM);
      bake(g, primitive, Mat4{}, false);
      lib.rtcAttachGeometry(prototype, g);
      prototypeGeometries_.push_back(g);
      prototypePrimitive_[m].push_back(int(p));
    }
    lib.rtcCommitScene(prototype);
    prototypes_[m] = prototype;
  }

  top_ = lib.rtcNewScene(device);
  if (!top_) throw std::runtime_error(lib.label + ": rtcNewScene failed");
  if (animated) {
    lib.rtcSetSceneFlags(top_, RTC_SCENE_FLAG_DYNAMIC);
    lib.rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_LOW);
  } else {
    lib.rtcSetSceneBuildQuality(top_, quality);
  }
  for (size_t placement = 0; placement < pose.meshes.size(); ++placement) {
    const PlacedMesh& placed = pose.meshes[placement];
    const Mesh& mesh = scene.meshes[size_t(placed.mesh)];
    if (prototypes_[size_t(placed.mesh)]) {
      RTCGeometry g = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
      lib.rtcSetGeometryInstancedScene(g, prototypes_[size_t(placed.mesh)]);
      lib.rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, placed.toWorld.m.data());
      lib.rtcCommitGeometry(g);
      lib.rtcAttachGeometry(top_, g);
      geometries_.push_back({g, placed.mesh, int(placement), -1});
      ++instanceCount_;
      continue;
    }
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      if (mesh.primitives[p].triangleCount() == 0) continue;
      RTCGeometry g = newTriangles(lib, device, mesh.primitives[p], geometryQuality);
      bake(g, mesh.primitives[p], placed.toWorld, false);
      lib.rtcAttachGeometry(top_, g);
      geometries_.push_back({g, placed.mesh, int(placement), int(p)});
    }
  }
  lib.rtcCommitScene(top_);
}

void CommittedRenderScene::bake(RTCGeometry geometry, const Primitive& primitive, const Mat4& toWorld, bool refit) const {
  auto* out = static_cast<float*>(lib_.rtcGetGeometryBufferData(geometry, RTC_BUFFER_TYPE_VERTEX, 0));
  for (size_t v = 0; v < primitive.vertexCount(); ++v) {
    const Vec3 w = transformPoint(toWorld, {primitive.positions[3 * v], primitive.positions[3 * v + 1], primitive.positions[3 * v + 2]});
    out[3 * v] = w.x, out[3 * v + 1] = w.y, out[3 * v + 2] = w.z;
  }
  if (refit) lib_.rtcUpdateGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0);
  lib_.rtcCommitGeometry(geometry);
}

void CommittedRenderScene::update(const ScenePose& pose) {
  for (const TopGeometry& top : geometries_) {
    const PlacedMesh& placed = pose.meshes.at(size_t(top.placement));
    if (top.primitive < 0) {
      lib_.rtcSetGeometryTransform(top.geometry, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, placed.toWorld.m.data());
      lib_.rtcCommitGeometry(top.geometry);
    } else {
      bake(top.geometry, scene_.meshes[size_t(placed.mesh)].primitives[size_t(top.primitive)], placed.toWorld, true);
    }
  }
  lib_.rtcCommitScene(top_);
}

HitLocation CommittedRenderScene::locate(const RTCHit& hit) const {
  if (hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
    const TopGeometry& top = geometries_.at(hit.instID[0]);
    return {top.placement, prototypePrimitive_.at(size_t(top.mesh)).at(hit.geomID)};
  }
  const TopGeometry& top = geometries_.at(hit.geomID);
  return {top.placement, top.primitive};
}

CommittedRenderScene::~CommittedRenderScene() {
  for (const TopGeometry& top : geometries_) lib_.rtcReleaseGeometry(top.geometry);
  for (RTCGeometry g : prototypeGeometries_) lib_.rtcReleaseGeometry(g);
  for (RTCScene s : prototypes_)
    if (s) lib_.rtcReleaseScene(s);
  if (top_) lib_.rtcReleaseScene(top_);
}

}  // namespace obvh::render
