// The camera rays are generated from: a glTF camera placed by its node, or an automatic view that
// frames the scene's bounds (orthographic by default, the semiconductor-viewer mode).
#pragma once

#include <string>

#include "render_scene.h"

namespace obvh::render {

struct ViewCamera {
  bool orthographic = false;
  Vec3 origin, forward, right, up;  // right and up scaled to half the image plane at unit distance (or half extents)
  float nearClip = 0.f;

  // (x, y): image coordinates in pixels, y down, pixel centres at +0.5.
  void ray(float x, float y, int width, int height, Vec3& org, Vec3& dir) const;
};

// The index-th placed camera of the pose (its node's world transform; -Z forward, +Y up).
ViewCamera sceneCamera(const RenderScene& scene, const ScenePose& pose, size_t index, int width, int height);

// Looks at the centre of the bounds from a fixed diagonal direction and frames them.
ViewCamera autoCamera(const Bounds& bounds, bool orthographic, int width, int height);

}  // namespace obvh::render

namespace obvh::render {

enum class Projection { FromScene, Orthographic, Perspective };

// The scene's index-th camera when it has one and `projection` is FromScene; otherwise an automatic
// view (orthographic unless Perspective is asked for). `description` says which was taken.
ViewCamera chooseCamera(const RenderScene& scene, const ScenePose& pose, size_t index, Projection projection,
                        int width, int height, std::string& description);

}  // namespace obvh::render
