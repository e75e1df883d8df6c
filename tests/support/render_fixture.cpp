#include "render_fixture.h"

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "committed_scene.h"
#include "integrator.h"
#include "showcase_scenes.h"
#include "view_camera.h"

namespace obvh::test {

std::string showcaseScenePath(const std::string& name) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  const std::filesystem::path dir = std::filesystem::path(OBVH_TEST_WORK_DIR) / "render_scenes";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / (name + ".gltf")).string();
  if (!std::filesystem::exists(path)) tools::writeShowcaseScene(name, path);
  return path;
}

std::string webxrControllerPath() {
  const char* data = std::getenv("OBVH_DATA");
  const std::filesystem::path root = data ? data : OBVH_DEFAULT_DATA_DIR;
  const std::filesystem::path path = root / "webxr" / "magicleap-two.glb";
  if (!std::filesystem::exists(path))
    throw std::runtime_error(path.string() + " is missing: run tools/setup/fetch_render_assets.sh (tools/setup/test.sh does)");
  return path.string();
}

RenderResult renderScene(const tools::RtcLibrary& lib, RTCDevice device, const render::RenderScene& scene,
                         const RenderRequest& request) {
  using namespace render;
  const ScenePose start = poseAt(scene, request.updateFromTimeZero ? 0.f : request.time);
  RenderResult result;
  result.plan = planEffects(scene, start, request.disabled);
  CommittedRenderScene committed(lib, device, scene, start, request.updateFromTimeZero);
  const ScenePose pose = poseAt(scene, request.time);
  if (request.updateFromTimeZero) committed.update(pose);
  FrameSettings settings;
  settings.width = request.width, settings.height = request.height;
  settings.samplesPerPixel = request.samplesPerPixel > 0 ? request.samplesPerPixel
                                                         : (result.plan.dispersion ? 64 : result.plan.pathTracing ? 16 : 1);
  settings.progress = false;
  settings.heatmap = request.heatmap;
  std::string description;
  const ViewCamera camera = chooseCamera(scene, pose, 0, Projection::FromScene, settings.width, settings.height, description);
  const Integrator integrator(lib, committed, scene, pose, result.plan, IntegratorSettings{});
  result.frame = renderFrame(integrator, camera, settings);
  return result;
}

}  // namespace obvh::test
