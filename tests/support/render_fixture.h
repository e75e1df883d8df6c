// Renders scenes for the renderer tests: the showcase scenes written once into the build tree,
// real assets found where the set-up scripts put them, and one-call renders through a library.
#pragma once

#include <set>
#include <string>

#include "effects.h"
#include "render_scene.h"
#include "renderer.h"
#include "rtc_library.h"

namespace obvh::test {

// Path of the named showcase scene (obvh_scenegen), generated on first use.
std::string showcaseScenePath(const std::string& name);

// The transmission/alpha glb from npm @webxr-input-profiles/assets (tools/setup/fetch_render_assets.sh).
std::string webxrControllerPath();

struct RenderRequest {
  float time = 0.f;
  bool updateFromTimeZero = false;  // commit the pose at t = 0, then update to `time` (refit / new transforms)
  std::set<render::Effect> disabled;
  int width = 160, height = 120;
  int samplesPerPixel = 0;  // 0: as obvh_render picks (1; 16 path tracing; 64 dispersion)
  bool heatmap = false;
};

struct RenderResult {
  render::Frame frame;
  render::EffectPlan plan;
};

RenderResult renderScene(const tools::RtcLibrary& lib, RTCDevice device, const render::RenderScene& scene,
                         const RenderRequest& request);

}  // namespace obvh::test
