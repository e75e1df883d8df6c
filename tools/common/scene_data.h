// Library-independent scene description: the same meshes are committed to Embree and to obvh.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <string>
#include <vector>

#include "rtc_library.h"

namespace obvh::tools {

struct MeshData {
  std::vector<float> vertices;     // x, y, z per vertex
  std::vector<uint32_t> indices;   // 3 (triangles) or 4 (quads) per primitive
  bool quads = false;
  bool grid = false;               // a grid mesh: its primitives are grids, indices is unused
  std::vector<RTCGrid> grids;
  // Motion blur: the vertices of time steps 1, 2, ... (step 0 is vertices), over [timeStart, timeEnd].
  std::vector<std::vector<float>> laterSteps;
  float timeStart = 0.f, timeEnd = 1.f;
  unsigned mask = 0xFFFFFFFFu;
  bool enabled = true;

  size_t vertexCount() const { return vertices.size() / 3; }
  unsigned timeStepCount() const { return unsigned(1 + laterSteps.size()); }
  // Whether a moving mesh is there at `time` (inside its time range); a still one always is.
  bool presentAt(float time) const;
  // Vertex index at a ray's time, blended as Embree and obvh blend time steps (in float); false
  // when the mesh is not there then.
  bool vertexAt(uint64_t index, float time, float out[3]) const;
  size_t primitiveCount() const { return grid ? grids.size() : indices.size() / (quads ? 4 : 3); }
};

struct SceneData {
  std::string name;
  std::vector<MeshData> meshes;  // geomID = position in this list
  size_t primitiveCount() const;
};

// A scene committed to one library; releases its handles on destruction.
class CommittedScene {
 public:
  CommittedScene(const RtcLibrary& lib, RTCDevice device, const SceneData& data,
                 RTCSceneFlags flags = RTC_SCENE_FLAG_NONE,
                 RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM);
  ~CommittedScene();
  CommittedScene(const CommittedScene&) = delete;
  CommittedScene& operator=(const CommittedScene&) = delete;

  RTCScene scene() const { return scene_; }
  RTCGeometry geometry(unsigned geomID) const { return geometries_.at(geomID); }
  // Re-reads every mesh's vertices (after the caller changed data) and commits again.
  void recommit(const SceneData& data);

 private:
  const RtcLibrary& lib_;
  RTCScene scene_ = nullptr;
  std::vector<RTCGeometry> geometries_;
};

// The closest-hit record a query returned, as plain values.
struct HitRecord {
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = RTC_INVALID_GEOMETRY_ID;
  float t = 0.f, u = 0.f, v = 0.f;
  float Ng[3] = {0.f, 0.f, 0.f};
  bool hit() const { return geomID != RTC_INVALID_GEOMETRY_ID; }
};

HitRecord toHitRecord(const RTCRayHit& rayhit);

}  // namespace obvh::tools
