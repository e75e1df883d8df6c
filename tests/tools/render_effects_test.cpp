// The renderer simulates exactly the effects a scene calls for: which are enabled is decided by
// inspecting the scene; turning off an effect the scene does not use leaves the image bit for bit
// unchanged, turning off one it uses changes it; the prism's dispersion spreads white into colours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render_fixture.h"
#include "scene_loader.h"

namespace obvh::test {
namespace {

using render::Effect;

const tools::RtcLibrary& obvhLibrary() {
  static std::unique_ptr<tools::RtcLibrary> lib = [] {
    std::string error;
    auto opened = tools::RtcLibrary::open(tools::obvhDropInPath(), "obvh", error);
    if (!opened) throw std::runtime_error(error);
    return opened;
  }();
  return *lib;
}

RTCDevice obvhDevice() {
  static RTCDevice device = obvhLibrary().rtcNewDevice(nullptr);
  return device;
}

struct Expectation {
  std::string scene;  // showcase name or a path
  std::set<Effect> enabled;
  std::string summaryStart;
};

render::RenderScene load(const std::string& scene) {
  return render::loadRenderScene(scene.find('/') == std::string::npos ? showcaseScenePath(scene) : scene);
}

const std::vector<Effect> kAllEffects = {Effect::Shadows, Effect::Transparency, Effect::PathTracing, Effect::Dispersion,
                                         Effect::Animation};

std::vector<Expectation> expectations() {
  return {
      {"shadows", {Effect::Shadows}, "effects: lambert, shadows (3 lights); skipped: transparency (no alpha)"},
      {"alpha", {Effect::Shadows, Effect::Transparency}, "effects: lambert, shadows (1 light), transparency (4 alpha materials)"},
      {"prism", {Effect::Shadows, Effect::PathTracing, Effect::Dispersion},
       "effects: lambert, shadows (1 light), path-tracing (1 transmissive material), dispersion (spectral"},
      {"animated", {Effect::Shadows, Effect::Animation}, "effects: lambert, shadows (1 light), animation (2 channels, 2.00 s)"},
      {"/usr/share/glmark2/models/bunny.obj", {}, "effects: lambert (headlight); skipped: shadows (no lights), transparency (no alpha)"},
      {webxrControllerPath(), {Effect::Transparency, Effect::PathTracing},
       "effects: lambert (headlight), transparency (1 alpha material), path-tracing (1 transmissive material); "
       "skipped: shadows (no lights), dispersion (no dispersive material)"},
  };
}

TEST(RenderEffects, EachSceneEnablesWhatItCallsFor) {
  for (const Expectation& e : expectations()) {
    const render::RenderScene scene = load(e.scene);
    const render::EffectPlan plan = render::planEffects(scene, render::poseAt(scene, 0.f));
    for (Effect effect : kAllEffects)
      EXPECT_EQ(plan.enabled(effect), e.enabled.count(effect) == 1) << e.scene << ": " << render::effectName(effect);
    EXPECT_EQ(plan.summary.rfind(e.summaryStart, 0), 0u) << e.scene << "\n  got: " << plan.summary;
  }
}

bool sameImage(const render::Frame& a, const render::Frame& b) { return a.rgb == b.rgb; }

TEST(RenderEffects, DisablingAnUnusedEffectChangesNothingAndAUsedOneChangesTheImage) {
  for (const Expectation& e : expectations()) {
    const render::RenderScene scene = load(e.scene);
    RenderRequest request;
    request.width = 96, request.height = 72, request.samplesPerPixel = 4;
    request.time = 0.6f;
    const render::Frame full = renderScene(obvhLibrary(), obvhDevice(), scene, request).frame;
    for (Effect effect : kAllEffects) {
      RenderRequest without = request;
      without.disabled = {effect};
      const RenderResult result = renderScene(obvhLibrary(), obvhDevice(), scene, without);
      EXPECT_FALSE(result.plan.enabled(effect));
      if (!e.enabled.count(effect)) {
        EXPECT_TRUE(sameImage(full, result.frame)) << e.scene << ": disabling unused " << render::effectName(effect);
      } else if (effect != Effect::Animation) {
        // Animation only decides whether frames are updated; a single frame at one time is the same.
        EXPECT_FALSE(sameImage(full, result.frame)) << e.scene << ": disabling used " << render::effectName(effect);
      }
    }
  }
}

// Hue in degrees of a linear RGB colour, or -1 when it is too grey or too dark to have one.
double hueOf(const float* c) {
  const float hi = std::max({c[0], c[1], c[2]}), lo = std::min({c[0], c[1], c[2]});
  if (hi < 0.05f || hi - lo < 0.5f * hi) return -1.0;
  double h;
  if (hi == c[0]) h = 60.0 * std::fmod((c[1] - c[2]) / (hi - lo), 6.0);
  else if (hi == c[1]) h = 60.0 * ((c[2] - c[0]) / (hi - lo) + 2.0);
  else h = 60.0 * ((c[0] - c[1]) / (hi - lo) + 4.0);
  return h < 0 ? h + 360.0 : h;
}

// Saturated pixels per 60-degree hue sector.
std::array<size_t, 6> hueHistogram(const render::Frame& frame) {
  std::array<size_t, 6> sectors{};
  for (size_t p = 0; p < frame.rgb.size() / 3; ++p) {
    const double h = hueOf(&frame.rgb[3 * p]);
    if (h >= 0) ++sectors[size_t(h / 60.0) % 6];
  }
  return sectors;
}

TEST(RenderEffects, PrismSpreadsWhiteLightIntoASpectrum) {
  const render::RenderScene scene = load("prism");
  RenderRequest request;
  request.width = 320, request.height = 240;
  const render::Frame spectral = renderScene(obvhLibrary(), obvhDevice(), scene, request).frame;
  request.disabled = {Effect::Dispersion};
  const render::Frame plain = renderScene(obvhLibrary(), obvhDevice(), scene, request).frame;
  const std::array<size_t, 6> withDispersion = hueHistogram(spectral), without = hueHistogram(plain);
  std::printf("[prism] saturated pixels per hue sector (red, yellow, green, cyan, blue, magenta):\n"
              "        dispersion %zu %zu %zu %zu %zu %zu; without %zu %zu %zu %zu %zu %zu\n",
              withDispersion[0], withDispersion[1], withDispersion[2], withDispersion[3], withDispersion[4], withDispersion[5],
              without[0], without[1], without[2], without[3], without[4], without[5]);
  // Red, yellow-green and green-cyan-blue light leave the prism at different angles: each of
  // those parts of the spectrum lights its own pixels.
  EXPECT_GT(withDispersion[0], 200u);
  EXPECT_GT(withDispersion[1] + withDispersion[2], 200u);
  EXPECT_GT(withDispersion[3] + withDispersion[4], 20u);
  // Without dispersion the glass bends all wavelengths alike: white stays white.
  size_t saturatedWithout = 0;
  for (size_t n : without) saturatedWithout += n;
  EXPECT_LT(saturatedWithout, 20u);
}

// --heatmap: obvh counts the bounding-volume tests of every pixel's rays; Embree cannot, and says so.
TEST(RenderHeatmap, CountsBoundingVolumeTestsOnObvhAndRefusesEmbree) {
  const render::RenderScene bunny = render::loadRenderScene("/usr/share/glmark2/models/bunny.obj");
  RenderRequest request;
  request.heatmap = true;
  const render::Frame frame = renderScene(obvhLibrary(), obvhDevice(), bunny, request).frame;
  ASSERT_EQ(frame.volumeTests.size(), size_t(request.width) * size_t(request.height));
  // Pixels showing the bunny traverse deeper than background pixels, which mostly stop at the root.
  const float background = frame.rgb[0];
  double onBunny = 0, offBunny = 0;
  size_t bunnyPixels = 0;
  for (size_t p = 0; p < frame.volumeTests.size(); ++p) {
    if (frame.rgb[3 * p] != background) onBunny += frame.volumeTests[p], ++bunnyPixels;
    else offBunny += frame.volumeTests[p];
  }
  ASSERT_GT(bunnyPixels, 1000u);
  const double meanOn = onBunny / double(bunnyPixels), meanOff = offBunny / double(frame.volumeTests.size() - bunnyPixels);
  std::printf("[heatmap] bunny: %.1f tests per bunny pixel, %.1f per background pixel\n", meanOn, meanOff);
  EXPECT_GT(meanOn, 16.0);
  EXPECT_GT(meanOn, 2.0 * meanOff);

  std::string error;
  auto embree = tools::RtcLibrary::open(tools::referenceEmbreePath(), "embree", error);
  ASSERT_TRUE(embree) << error;
  RTCDevice device = embree->rtcNewDevice("isa=avx2");
  try {
    renderScene(*embree, device, bunny, request);
    ADD_FAILURE() << "a heatmap through Embree should be refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("does not count bounding-volume tests"), std::string::npos) << e.what();
  }
  embree->rtcReleaseDevice(device);
}

}  // namespace
}  // namespace obvh::test
