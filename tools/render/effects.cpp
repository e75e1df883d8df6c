#include "effects.h"

#include <stdexcept>
#include <vector>

namespace obvh::render {

Effect parseEffect(const std::string& name) {
  for (Effect e : {Effect::Shadows, Effect::Transparency, Effect::PathTracing, Effect::Dispersion, Effect::Animation})
    if (name == effectName(e)) return e;
  throw std::runtime_error("unknown effect '" + name + "' (shadows, transparency, path-tracing, dispersion, animation)");
}

const char* effectName(Effect effect) {
  switch (effect) {
    case Effect::Shadows: return "shadows";
    case Effect::Transparency: return "transparency";
    case Effect::PathTracing: return "path-tracing";
    case Effect::Dispersion: return "dispersion";
    case Effect::Animation: return "animation";
  }
  return "?";
}

bool EffectPlan::enabled(Effect effect) const {
  switch (effect) {
    case Effect::Shadows: return shadows;
    case Effect::Transparency: return transparency;
    case Effect::PathTracing: return pathTracing;
    case Effect::Dispersion: return dispersion;
    case Effect::Animation: return animation;
  }
  return false;
}

namespace {

bool hasAlpha(const RenderScene& scene, const Material& m) {
  if (m.alphaMode == AlphaMode::Mask) return true;
  if (m.alphaMode != AlphaMode::Blend) return false;
  if (m.baseColor[3] < 1.f) return true;
  if (m.baseColorTexture < 0) return false;
  const Texture& t = scene.textures[size_t(m.baseColorTexture)];
  for (size_t p = 3; p < t.rgba.size(); p += 4)
    if (t.rgba[p] < 1.f) return true;
  return false;
}

std::string count(size_t n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); }

}  // namespace

EffectPlan planEffects(const RenderScene& scene, const ScenePose& pose, const std::set<Effect>& disabled) {
  std::set<int> used;
  for (const PlacedMesh& placed : pose.meshes)
    for (const Primitive& p : scene.meshes[size_t(placed.mesh)].primitives) used.insert(p.material);
  size_t alpha = 0, transmissive = 0, dispersive = 0;
  for (int index : used) {
    const Material& m = scene.material(index);
    alpha += hasAlpha(scene, m);
    transmissive += m.transmission > 0.f;
    dispersive += m.transmission > 0.f && m.dispersion > 0.f;
  }
  size_t channels = 0;
  for (const Animation& a : scene.animations) channels += a.channels.size();

  EffectPlan plan;
  std::vector<std::string> on{pose.lights.empty() ? "lambert (headlight)" : "lambert"}, off;
  const auto decide = [&](Effect effect, bool wanted, const std::string& why, const std::string& whyNot) {
    const bool turnedOff = wanted && disabled.count(effect);
    if (wanted && !turnedOff) on.push_back(std::string(effectName(effect)) + " (" + why + ")");
    else off.push_back(std::string(effectName(effect)) + " (" + (turnedOff ? "disabled by --disable" : whyNot) + ")");
    return wanted && !turnedOff;
  };
  plan.shadows = decide(Effect::Shadows, !pose.lights.empty(), count(pose.lights.size(), "light", "lights"), "no lights");
  plan.transparency = decide(Effect::Transparency, alpha > 0, count(alpha, "alpha material", "alpha materials"), "no alpha");
  plan.pathTracing = decide(Effect::PathTracing, transmissive > 0, count(transmissive, "transmissive material", "transmissive materials"),
                            "no transmission");
  plan.dispersion = decide(Effect::Dispersion, dispersive > 0 && plan.pathTracing,
                           "spectral, " + count(dispersive, "dispersive material", "dispersive materials"),
                           transmissive > 0 && dispersive > 0 ? "needs path tracing" : "no dispersive material");
  plan.animation = decide(Effect::Animation, channels > 0,
                          count(channels, "channel", "channels") + ", " + std::to_string(scene.animationDuration()).substr(0, 4) + " s",
                          "static scene");
  plan.summary = "effects: ";
  for (size_t i = 0; i < on.size(); ++i) plan.summary += (i ? ", " : "") + on[i];
  plan.summary += "; skipped: ";
  for (size_t i = 0; i < off.size(); ++i) plan.summary += (i ? ", " : "") + off[i];
  if (off.empty()) plan.summary += "none";
  return plan;
}

}  // namespace obvh::render
