// Radiance along one camera ray, simulating only the effects the plan enables:
//  - direct: Lambert with a headlight (no lights) or with the scene's punctual lights, shadow rays
//    when it has lights, ordered alpha compositing along the ray when it has alpha materials;
//  - path tracing (transmission): diffuse and dielectric (Fresnel reflection / refraction) paths,
//    next-event estimation of punctual lights; with dispersion, each path carries one wavelength.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

#include "committed_scene.h"
#include "effects.h"
#include "render_scene.h"
#include "rtc_library.h"
#include "sampler.h"

namespace obvh::render {

// One query the integrator sent, with the library's answer (for replaying a pixel in the render
// cross-validation).
struct LoggedQuery {
  bool occlusion = false;
  RTCRayHit query{};   // as sent
  RTCRayHit answer{};  // as returned (occlusion: only the ray, tfar = -inf when occluded)
};

struct IntegratorSettings {
  int maxDepth = 8;          // path vertices per path
  int maxLayers = 32;        // alpha layers composited per ray
  float headlightAmbient = 0.15f;
};

class Integrator {
 public:
  Integrator(const tools::RtcLibrary& lib, const CommittedRenderScene& committed, const RenderScene& scene,
             const ScenePose& pose, const EffectPlan& plan, const IntegratorSettings& settings);

  // Linear RGB radiance; `rays` counts the queries this sample sent to the library. spectralU in
  // [0, 1) picks the wavelength of a dispersive path (the renderer stratifies it over a pixel's samples).
  Vec3 radiance(Vec3 org, Vec3 dir, Sampler& sampler, float spectralU, uint64_t& rays) const;

  // Background seen by rays that leave the scene: a white sky lights path-traced scenes without
  // punctual lights; otherwise a dim background.
  float environment() const { return environment_; }

  const tools::RtcLibrary& library() const { return lib_; }

  // Appends every query and answer to `log` (nullptr stops). Only for single-threaded replays.
  void recordQueries(std::vector<LoggedQuery>* log) { log_ = log; }

 private:
  // One rtcIntersect1 / rtcOccluded1 over (0, tfar], counted and logged. cameraRay: the query
  // carries Embree's coherence hint (RTC_INTERSECT_CONTEXT_FLAG_COHERENT), as camera rays of
  // neighbouring pixels are; bounces keep the default (incoherent) context.
  bool intersect(Vec3 org, Vec3 dir, float tfar, RTCRayHit& rayhit, uint64_t& rays, bool cameraRay = false) const;
  bool occluded(Vec3 org, Vec3 dir, float tfar, uint64_t& rays) const;
  // Fraction of light arriving along the segment (1 free, 0 blocked); partial through alpha layers.
  float transmittance(Vec3 org, Vec3 dir, float distance, uint64_t& rays) const;
  // Punctual lights reflected by a diffuse surface towards the viewer (per-channel, rgb weights).
  Vec3 directLight(const struct Surface& s, uint64_t& rays) const;
  Vec3 shadeDirect(Vec3 org, Vec3 dir, uint64_t& rays) const;
  Vec3 tracePath(Vec3 org, Vec3 dir, Sampler& sampler, float wavelength, uint64_t& rays) const;

  const tools::RtcLibrary& lib_;
  const CommittedRenderScene& committed_;
  const RenderScene& scene_;
  const ScenePose& pose_;
  EffectPlan plan_;
  IntegratorSettings settings_;
  float environment_ = 0.f;
  std::vector<LoggedQuery>* log_ = nullptr;
};

}  // namespace obvh::render
