// Which rendering effects a scene calls for, decided by inspecting it: the renderer simulates only
// those, and says at start what it enabled and what it skipped and why.
#pragma once

#include <set>
#include <string>

#include "render_scene.h"

namespace obvh::render {

enum class Effect { Shadows, Transparency, PathTracing, Dispersion, Animation };

// Parses "shadows", "transparency", "path-tracing", "dispersion", "animation"; throws on others.
Effect parseEffect(const std::string& name);
const char* effectName(Effect effect);

struct EffectPlan {
  bool shadows = false;       // punctual lights: direct light with shadow rays; else a headlight
  bool transparency = false;  // alpha blending / masking: ordered compositing along the ray
  bool pathTracing = false;   // transmission: diffuse + dielectric path tracing
  bool dispersion = false;    // dispersive transmission: one wavelength per path
  bool animation = false;     // node animation: per-frame update of the acceleration structure
  std::string summary;        // "effects: ...; skipped: ..."

  bool enabled(Effect effect) const;
};

// `disabled`: effects the user turned off (--disable); they are reported as skipped.
EffectPlan planEffects(const RenderScene& scene, const ScenePose& pose, const std::set<Effect>& disabled = {});

}  // namespace obvh::render
