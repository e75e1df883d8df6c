// Images rendered through obvh and through Debian's Embree must be identical (as 8-bit display
// values) except where a query's answer legitimately differs. Every differing pixel is replayed
// through both libraries with its queries logged; the first query whose answers differ decides:
//  - the same ray, answers judged ambiguous in double precision (or obvh's the exact one): ambiguous;
//  - rays already apart by float rounding of earlier hits, obvh's answer plausible for its own ray:
//    rounding (a path that grazed an edge differently after a last-bit difference);
//  - no answer differs beyond the tolerance of the hit comparison, pixel within 4/255: rounding;
//  - anything else: a mismatch, which fails the test.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <utility>

#include "committed_scene.h"
#include "crossval_harness.h"
#include "frame_output.h"
#include "hit_compare.h"
#include "integrator.h"
#include "render_fixture.h"
#include "scene_loader.h"
#include "scene_writer.h"
#include "stack_generator.h"
#include "view_camera.h"

namespace obvh::test {
namespace {

using namespace render;

// The posed scene flattened into world-space meshes, one per (placement, primitive), for the
// double-precision judges; hits of either library map onto it through locate().
struct FlatScene {
  tools::SceneData data;
  std::map<std::pair<int, int>, unsigned> geomID;
};

FlatScene flatten(const RenderScene& scene, const ScenePose& pose) {
  FlatScene flat;
  for (size_t placement = 0; placement < pose.meshes.size(); ++placement) {
    const PlacedMesh& placed = pose.meshes[placement];
    const Mesh& mesh = scene.meshes[size_t(placed.mesh)];
    for (size_t p = 0; p < mesh.primitives.size(); ++p) {
      const Primitive& primitive = mesh.primitives[p];
      if (primitive.triangleCount() == 0) continue;
      tools::MeshData m;
      for (size_t v = 0; v < primitive.vertexCount(); ++v) {
        const Vec3 w = transformPoint(placed.toWorld, {primitive.positions[3 * v], primitive.positions[3 * v + 1],
                                                       primitive.positions[3 * v + 2]});
        m.vertices.insert(m.vertices.end(), {w.x, w.y, w.z});
      }
      m.indices = primitive.indices;
      flat.geomID[{int(placement), int(p)}] = unsigned(flat.data.meshes.size());
      flat.data.meshes.push_back(std::move(m));
    }
  }
  return flat;
}

// One library's view of the scene: committed, with its integrator.
struct Side {
  Side(const tools::RtcLibrary& lib, RTCDevice device, const RenderScene& scene, const ScenePose& start,
       const ScenePose& pose, bool update, const EffectPlan& plan)
      : committed(lib, device, scene, start, update), integrator(lib, committed, scene, pose, plan, IntegratorSettings{}) {
    if (update) committed.update(pose);
  }
  CommittedRenderScene committed;
  Integrator integrator;
};

struct PixelCounts {
  size_t pixels = 0, differing = 0, ambiguous = 0, rounding = 0, mismatched = 0;
  std::vector<std::string> examples;
};

tools::HitRecord record(const FlatScene& flat, const CommittedRenderScene& committed, const RTCRayHit& answer) {
  tools::HitRecord h = tools::toHitRecord(answer);
  if (h.hit()) {
    const HitLocation where = committed.locate(answer.hit);
    h.geomID = flat.geomID.at({where.placement, where.primitive});
  }
  return h;
}

enum class Cause { Ambiguous, Rounding, Mismatch };

Cause classify(const FlatScene& flat, Side& embree, Side& obvh, const ViewCamera& camera, const FrameSettings& settings,
               int x, int y, double pixelError, std::string& why) {
  std::vector<LoggedQuery> logE, logO;
  uint64_t rays = 0;
  embree.integrator.recordQueries(&logE);
  obvh.integrator.recordQueries(&logO);
  renderPixel(embree.integrator, camera, settings, x, y, rays);
  renderPixel(obvh.integrator, camera, settings, x, y, rays);
  embree.integrator.recordQueries(nullptr);
  obvh.integrator.recordQueries(nullptr);
  for (size_t i = 0; i < std::min(logE.size(), logO.size()); ++i) {
    const LoggedQuery& e = logE[i];
    const LoggedQuery& o = logO[i];
    const bool sameRay = std::memcmp(&e.query.ray, &o.query.ray, sizeof(RTCRay)) == 0;
    if (e.occlusion != o.occlusion) {
      why = "query " + std::to_string(i) + ": the paths took different branches with equal answers before";
      return Cause::Mismatch;
    }
    if (e.occlusion) {
      const bool occE = e.answer.ray.tfar < 0.f, occO = o.answer.ray.tfar < 0.f;
      if (occE == occO) continue;
      if (!sameRay) return Cause::Rounding;
      const tools::OcclusionTruth truth = tools::exactOcclusion(flat.data, e.query.ray);
      if (truth == tools::OcclusionTruth::Ambiguous || (truth == tools::OcclusionTruth::Occluded) == occO) {
        if (std::getenv("OBVH_RENDER_DEBUG")) std::printf("ambiguous shadow query %zu: truth %d obvh %d\n", i, int(truth), int(occO));
        return Cause::Ambiguous;
      }
      why = "shadow ray " + tools::describeRay(e.query.ray) + ": obvh " + (occO ? "occluded" : "free") + ", exact answer differs";
      return Cause::Mismatch;
    }
    const tools::HitRecord hE = record(flat, embree.committed, e.answer), hO = record(flat, obvh.committed, o.answer);
    if (!sameRay) {
      if (hE.geomID == hO.geomID && hE.primID == hO.primID) continue;
      if (!hO.hit() || tools::hitIsPlausible(flat.data, o.query.ray, hO.geomID, hO.primID)) return Cause::Rounding;
      why = "query " + std::to_string(i) + ": obvh's hit is implausible for its own ray " + tools::describeRay(o.query.ray);
      return Cause::Mismatch;
    }
    const tools::Comparison c = tools::compareHits(flat.data, e.query.ray, hE, hO);
    if (c.verdict == tools::Verdict::Equal) continue;
    if (c.verdict == tools::Verdict::Ambiguous) {
      if (std::getenv("OBVH_RENDER_DEBUG")) std::printf("ambiguous query %zu: %s\n", i, c.reason.c_str());
      return Cause::Ambiguous;
    }
    why = "query " + std::to_string(i) + " " + tools::describeRay(e.query.ray) + ": " + c.reason;
    return Cause::Mismatch;
  }
  if (logE.size() != logO.size()) {
    why = "the paths sent " + std::to_string(logE.size()) + " and " + std::to_string(logO.size()) + " queries with equal answers";
    return Cause::Mismatch;
  }
  if (pixelError <= 4.0 / 255.0) return Cause::Rounding;
  why = "every answer equal within tolerance, yet the pixel differs by " + std::to_string(pixelError);
  return Cause::Mismatch;
}

// candidate: the scene obvh renders; the same as `scene` except in the test that proves the judge
// catches a real difference.
PixelCounts compareRenders(const RenderScene& scene, const RenderRequest& request, const RenderScene* candidate = nullptr) {
  const LoadedLibraries& libs = libraries();
  const ScenePose start = poseAt(scene, request.updateFromTimeZero ? 0.f : request.time);
  const ScenePose pose = poseAt(scene, request.time);
  const EffectPlan plan = planEffects(scene, start, request.disabled);
  const RenderScene& obvhScene = candidate ? *candidate : scene;
  Side embree(*libs.embree, libs.embreeDevice, scene, start, pose, request.updateFromTimeZero, plan);
  const ScenePose obvhStart = poseAt(obvhScene, request.updateFromTimeZero ? 0.f : request.time);
  const ScenePose obvhPose = poseAt(obvhScene, request.time);
  Side obvh(*libs.obvh, libs.obvhDevice, obvhScene, obvhStart, obvhPose, request.updateFromTimeZero, plan);
  FrameSettings settings;
  settings.width = request.width, settings.height = request.height, settings.progress = false;
  settings.samplesPerPixel = request.samplesPerPixel > 0 ? request.samplesPerPixel : (plan.dispersion ? 64 : plan.pathTracing ? 16 : 1);
  std::string description;
  const ViewCamera camera = chooseCamera(scene, pose, 0, Projection::FromScene, settings.width, settings.height, description);
  const Frame frameE = renderFrame(embree.integrator, camera, settings);
  const Frame frameO = renderFrame(obvh.integrator, camera, settings);
  const FlatScene flat = flatten(scene, pose);

  PixelCounts counts;
  counts.pixels = size_t(settings.width) * size_t(settings.height);
  for (size_t p = 0; p < counts.pixels; ++p) {
    double error = 0.0;
    for (int c = 0; c < 3; ++c)
      error = std::max(error, std::abs(int(displayValue(frameE.rgb[3 * p + size_t(c)])) - int(displayValue(frameO.rgb[3 * p + size_t(c)]))) / 255.0);
    if (error == 0.0) continue;
    ++counts.differing;
    std::string why;
    switch (classify(flat, embree, obvh, camera, settings, int(p % size_t(settings.width)), int(p / size_t(settings.width)), error, why)) {
      case Cause::Ambiguous: ++counts.ambiguous; break;
      case Cause::Rounding: ++counts.rounding; break;
      case Cause::Mismatch:
        ++counts.mismatched;
        if (counts.examples.size() < 5) counts.examples.push_back("pixel " + std::to_string(p) + ": " + why);
        break;
    }
  }
  return counts;
}

void expectImagesAgree(const char* what, const PixelCounts& c) {
  std::printf("[render] %-28s %zu pixels: %zu differ (%zu ambiguous, %zu rounding, %zu mismatched)\n", what, c.pixels,
              c.differing, c.ambiguous, c.rounding, c.mismatched);
  ::testing::Test::RecordProperty(std::string(what) + "_differing", int(c.differing));
  EXPECT_EQ(c.mismatched, 0u) << what << ": " << (c.examples.empty() ? "" : c.examples[0]);
  // A few rounding-level pixels are expected; a flood of them means something systematic.
  EXPECT_LE(c.differing, c.pixels / 200) << what;
}

RenderRequest vga() {
  RenderRequest request;
  request.width = 640, request.height = 480;
  return request;
}

TEST(RenderCrossval, ShowcaseShadows) {
  expectImagesAgree("shadows", compareRenders(loadRenderScene(showcaseScenePath("shadows")), vga()));
}

TEST(RenderCrossval, ShowcaseAlpha) {
  expectImagesAgree("alpha", compareRenders(loadRenderScene(showcaseScenePath("alpha")), vga()));
}

// The judge itself: obvh given a box moved by 1% of its size must be caught.
TEST(RenderCrossval, JudgeCatchesAMovedBox) {
  const RenderScene scene = loadRenderScene(showcaseScenePath("shadows"));
  RenderScene moved = scene;
  for (Node& node : moved.nodes)
    if (node.name == "red box") node.translation.x += 0.01f;
  const PixelCounts counts = compareRenders(scene, vga(), &moved);
  std::printf("[render] judge on a moved box: %zu differ, %zu mismatched\n", counts.differing, counts.mismatched);
  EXPECT_GT(counts.mismatched, 50u);
}

TEST(RenderCrossval, ShowcasePrismSpectral) {
  RenderRequest request;
  request.width = 320, request.height = 240;
  request.samplesPerPixel = 16;
  expectImagesAgree("prism", compareRenders(loadRenderScene(showcaseScenePath("prism")), request));
}

TEST(RenderCrossval, ShowcaseAnimatedAfterUpdate) {
  RenderRequest request = vga();
  request.time = 0.7f;
  request.updateFromTimeZero = true;  // refit of the sliding box, new instance transforms of the carousel
  expectImagesAgree("animated t=0.7 (updated)", compareRenders(loadRenderScene(showcaseScenePath("animated")), request));
}

TEST(RenderCrossval, Bunny) {
  RenderRequest request;
  request.width = 512, request.height = 384;
  expectImagesAgree("bunny", compareRenders(loadRenderScene("/usr/share/glmark2/models/bunny.obj"), request));
}

TEST(RenderCrossval, GeneratedStack) {
  const std::string path = std::string(OBVH_TEST_WORK_DIR) + "/render_scenes/diagonal-42k.glb";
  const tools::StackPreset* preset = tools::findStackPreset("diagonal-42k");
  ASSERT_NE(preset, nullptr);
  showcaseScenePath("shadows");  // creates the directory
  tools::writeStackScene(tools::generateStack(preset->params, preset->name), path);
  RenderRequest request;
  request.width = 512, request.height = 384;
  expectImagesAgree("stack diagonal-42k", compareRenders(loadRenderScene(path), request));
}

TEST(RenderCrossval, WebxrControllerTransmissionAndBlend) {
  RenderRequest request;
  request.width = 320, request.height = 240;
  request.samplesPerPixel = 8;
  expectImagesAgree("webxr magicleap-two", compareRenders(loadRenderScene(webxrControllerPath()), request));
}

}  // namespace
}  // namespace obvh::test
