#include "view_camera.h"

#include <cmath>
#include <stdexcept>

namespace obvh::render {

void ViewCamera::ray(float x, float y, int width, int height, Vec3& org, Vec3& dir) const {
  const float sx = 2.f * x / float(width) - 1.f, sy = 1.f - 2.f * y / float(height);
  if (orthographic) {
    org = origin + right * sx + up * sy;
    dir = forward;
  } else {
    org = origin;
    dir = normalize(forward + right * sx + up * sy);
  }
}

ViewCamera sceneCamera(const RenderScene& scene, const ScenePose& pose, size_t index, int width, int height) {
  const PlacedCamera& placed = pose.cameras.at(index);
  const Camera& camera = scene.cameras.at(size_t(placed.camera));
  ViewCamera view;
  view.orthographic = camera.orthographic;
  view.origin = transformPoint(placed.toWorld, Vec3{0.f});
  view.forward = normalize(transformVector(placed.toWorld, {0.f, 0.f, -1.f}));
  const Vec3 right = normalize(transformVector(placed.toWorld, {1.f, 0.f, 0.f}));
  const Vec3 up = normalize(transformVector(placed.toWorld, {0.f, 1.f, 0.f}));
  // The image's own aspect, as glTF viewers do: the file's aspectRatio would stretch other sizes.
  const float aspect = float(width) / float(height);
  if (camera.orthographic) {
    view.right = right * std::fabs(camera.xmag);
    view.up = up * std::fabs(camera.ymag);
  } else {
    const float halfHeight = std::tan(0.5f * camera.yfov);
    view.up = up * halfHeight;
    view.right = right * (halfHeight * aspect);
  }
  return view;
}

ViewCamera autoCamera(const Bounds& bounds, bool orthographic, int width, int height) {
  const Vec3 centre = (bounds.lower + bounds.upper) * 0.5f;
  const float radius = std::max(0.5f * length(bounds.upper - bounds.lower), 1e-6f);
  const Vec3 towardsEye = normalize(Vec3{0.55f, 0.45f, 0.7f});
  const float aspect = float(width) / float(height);
  ViewCamera view;
  view.orthographic = orthographic;
  view.forward = -towardsEye;
  Vec3 right = cross(view.forward, {0.f, 1.f, 0.f});
  right = normalize(right);
  const Vec3 up = cross(right, view.forward);
  const float fill = 1.05f;  // a margin around the bounding sphere
  if (orthographic) {
    const float half = radius * fill;
    view.origin = centre + towardsEye * (2.f * radius);
    view.up = up * (aspect >= 1.f ? half : half / aspect);
    view.right = right * (aspect >= 1.f ? half * aspect : half);
  } else {
    const float halfAngle = 0.35f;
    const float distance = radius * fill / std::sin(halfAngle);
    view.origin = centre + towardsEye * distance;
    const float t = std::tan(halfAngle);
    view.up = up * (aspect >= 1.f ? t : t / aspect);
    view.right = right * (aspect >= 1.f ? t * aspect : t);
  }
  return view;
}

}  // namespace obvh::render

namespace obvh::render {

ViewCamera chooseCamera(const RenderScene& scene, const ScenePose& pose, size_t index, Projection projection,
                        int width, int height, std::string& description) {
  if (projection == Projection::FromScene && !pose.cameras.empty()) {
    if (index >= pose.cameras.size())
      throw std::runtime_error("the scene has " + std::to_string(pose.cameras.size()) + " cameras; --camera " +
                               std::to_string(index) + " does not exist");
    const ViewCamera view = sceneCamera(scene, pose, index, width, height);
    description = std::string("scene camera ") + std::to_string(index) + (view.orthographic ? " (orthographic)" : " (perspective)");
    return view;
  }
  const bool orthographic = projection != Projection::Perspective;
  description = std::string("automatic ") + (orthographic ? "orthographic" : "perspective") + " view of the scene bounds" +
                (pose.cameras.empty() ? " (the scene has no camera)" : "");
  return autoCamera(worldBounds(scene, pose), orthographic, width, height);
}

}  // namespace obvh::render
