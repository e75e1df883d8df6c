// A RenderScene committed to one Embree 3 compatible library through its C API: a mesh placed once
// is baked into world space (one triangle geometry per primitive); a mesh placed several times is
// committed once in its own scene and referenced by instances. Animated frames update vertices
// (refit) and instance transforms, then commit again.
#pragma once

#include <embree3/rtcore.h>

#include <vector>

#include "render_scene.h"
#include "rtc_library.h"

namespace obvh::render {

// Which primitive of which placed mesh a hit is on.
struct HitLocation {
  int placement = -1;  // index into ScenePose::meshes
  int primitive = -1;  // index into that mesh's primitives
};

class CommittedRenderScene {
 public:
  // animated: the scene will be updated per frame (dynamic scene, refit geometries). quality: of
  // the top-level scene (and of instanced meshes' scenes) when not animated.
  CommittedRenderScene(const tools::RtcLibrary& lib, RTCDevice device, const RenderScene& scene, const ScenePose& pose,
                       bool animated, RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM);
  ~CommittedRenderScene();
  CommittedRenderScene(const CommittedRenderScene&) = delete;
  CommittedRenderScene& operator=(const CommittedRenderScene&) = delete;

  // Moves everything to a new pose of the same scene and commits (refit where topology is unchanged).
  void update(const ScenePose& pose);

  RTCScene handle() const { return top_; }
  HitLocation locate(const RTCHit& hit) const;
  size_t instanceCount() const { return instanceCount_; }

 private:
  struct TopGeometry {
    RTCGeometry geometry = nullptr;
    int mesh = -1;
    int placement = -1;
    int primitive = -1;  // baked primitive; -1 for an instance
  };
  void bake(RTCGeometry geometry, const Primitive& primitive, const Mat4& toWorld, bool refit) const;

  const tools::RtcLibrary& lib_;
  const RenderScene& scene_;
  RTCScene top_ = nullptr;
  std::vector<TopGeometry> geometries_;             // by top-level geomID
  std::vector<RTCScene> prototypes_;                // by mesh; null when the mesh is baked
  std::vector<std::vector<int>> prototypePrimitive_;  // by mesh: prototype geomID -> primitive
  std::vector<RTCGeometry> prototypeGeometries_;
  size_t instanceCount_ = 0;
};

}  // namespace obvh::render
