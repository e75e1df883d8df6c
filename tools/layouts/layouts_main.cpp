// obvh_layouts: the layout study. For each scene (stack presets, mesh files) and each BVH
// configuration (AABB, OBB with midpoint/median/SAH splits, hybrid, k-means leaf clusters) it
// prints SAH cost, depth std-dev, node/leaf counts, memory, build ms, render ms of a 1 spp
// orthographic and perspective view and bounding-volume tests per ray, with Debian's Embree's build
// and render times measured in the same run; optionally writes heatmaps of tests per pixel.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "layout_configs.h"
#include "layout_measure.h"
#include "triangle_scene_file.h"
#include "command_line.h"
#include "ray_generation.h"
#include "rtc_library.h"
#include "scene_data.h"
#include "stack_generator.h"
#include "trace_timing.h"

using namespace obvh::tools;

namespace {

struct Options {
  std::vector<std::string> presets, meshes, configs;
  int width = 1280, height = 720, runs = 3;
  std::string heatmapDir;
  bool embree = true;
};

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_layouts: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_layouts [--preset NAME]... [--all-presets] [--scene FILE.obj|.ply|.stl|.glb|.gltf]... [--configs A,B,...]\n"
               "                    [--width W] [--height H] [--runs N] [--heatmaps DIR] [--no-embree]\n"
               "  presets: obvh_stackgen --list; configs:");
  for (const LayoutConfig& c : layoutConfigs()) std::fprintf(stderr, " %s", c.name.c_str());
  std::fprintf(stderr, "\n  defaults: every config, 1280x720, median of 3 runs\n");
  std::exit(error.empty() ? 0 : 2);
}

int positive(const std::string& flag, const char* value) {
  const std::optional<long> v = parsePositiveNumber(value, 100000);
  if (!v) usage("invalid value '" + std::string(value) + "' for " + flag);
  return int(*v);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage("");
    if (arg == "--all-presets") {
      for (const StackPreset& p : stackPresets()) o.presets.push_back(p.name);
      continue;
    }
    if (arg == "--no-embree") {
      o.embree = false;
      continue;
    }
    if (i + 1 >= argc) usage("missing value for " + arg);
    const char* value = argv[++i];
    if (arg == "--preset") {
      if (!findStackPreset(value)) usage("unknown preset '" + std::string(value) + "' (see obvh_stackgen --list)");
      o.presets.push_back(value);
    } else if (arg == "--scene") {
      o.meshes.push_back(value);
    } else if (arg == "--configs") {
      std::stringstream list(value);
      std::string name;
      while (std::getline(list, name, ','))
        if (!findLayoutConfig(name)) usage("unknown config '" + name + "'");
        else o.configs.push_back(name);
    } else if (arg == "--width") {
      o.width = positive(arg, value);
    } else if (arg == "--height") {
      o.height = positive(arg, value);
    } else if (arg == "--runs") {
      o.runs = positive(arg, value);
    } else if (arg == "--heatmaps") {
      o.heatmapDir = value;
    } else {
      usage("unknown option " + arg);
    }
  }
  if (o.presets.empty() && o.meshes.empty()) usage("give at least one --preset, --all-presets or --scene");
  if (o.configs.empty())
    for (const LayoutConfig& c : layoutConfigs()) o.configs.push_back(c.name);
  return o;
}

SceneBox boundsOf(const SceneData& scene) {
  SceneBox box{{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()},
               {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()}};
  for (const MeshData& mesh : scene.meshes)
    for (size_t i = 0; i + 2 < mesh.vertices.size(); i += 3)
      for (int k = 0; k < 3; ++k) {
        box.lower[k] = std::min(box.lower[k], mesh.vertices[i + k]);
        box.upper[k] = std::max(box.upper[k], mesh.vertices[i + k]);
      }
  return box;
}

std::string fixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

void printHeader() {
  std::printf("| config | SAH cost | depth std | nodes | leaves | OBB nodes | MiB | build ms | ortho ms | persp ms | "
              "BV tests/ray ortho | BV tests/ray persp |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
}

void measureEmbree(const RtcLibrary& embree, const SceneData& scene, const std::vector<View>& views, int runs) {
  RTCDevice device = embree.rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("Embree: rtcNewDevice failed");
  std::vector<double> builds;
  std::unique_ptr<CommittedScene> committed;
  for (int r = 0; r < runs; ++r) {
    committed.reset();
    builds.push_back(millisecondsOf([&] { committed = std::make_unique<CommittedScene>(embree, device, scene); }));
  }
  std::string row = "| Embree 3.13.5 (MEDIUM) | | | | | | | " + fixed(median(builds), 1) + " |";
  for (const View& view : views) {
    const double mrays = traceIntersectMrays(embree, committed->scene(), view.rays, runs);
    row += " " + fixed(double(view.rays.size()) / (mrays * 1e3), 1) + " |";
  }
  std::printf("%s | |\n", row.c_str());
  committed.reset();
  embree.rtcReleaseDevice(device);
}

void study(const SceneData& scene, const std::string& label, const Options& o, const RtcLibrary* embree) {
  const SceneBox box = boundsOf(scene);
  std::vector<View> views = {{"ortho", o.width, o.height, orthographicRays(box, o.width, o.height)},
                             {"persp", o.width, o.height, perspectiveRays(box, o.width, o.height)}};
  std::printf("\n%s: %zu triangles/quads, %dx%d, 1 spp, median of %d runs\n\n", label.c_str(), scene.primitiveCount(),
              o.width, o.height, o.runs);
  printHeader();
  if (embree) measureEmbree(*embree, scene, views, o.runs);
  for (const std::string& name : o.configs) {
    const LayoutConfig& config = *findLayoutConfig(name);
    const LayoutMeasure m = measureLayout(scene, config, views, o.runs);
    std::string row = "| " + config.name + " (`" + config.deviceConfig + "`) | " + fixed(m.sahCost, 1) + " | " +
                      fixed(m.depthStdDev, 2) + " | " + std::to_string(m.nodeCount) + " | " +
                      std::to_string(m.leafCount) + " | " + std::to_string(m.orientedNodeCount) + " | " +
                      fixed(double(m.memoryBytes) / (1024.0 * 1024.0), 1) + " | " + fixed(m.buildMs, 1) + " |";
    for (const ViewMeasure& v : m.views) row += " " + fixed(v.renderMs, 1) + " |";
    for (const ViewMeasure& v : m.views) row += v.volumeTestsPerRay < 0 ? " - |" : " " + fixed(v.volumeTestsPerRay, 1) + " |";
    std::printf("%s\n", row.c_str());
    std::fflush(stdout);
    if (!o.heatmapDir.empty())
      for (size_t k = 0; k < views.size(); ++k) {
        if (m.views[k].testsPerPixel.empty()) continue;
        const std::string path = o.heatmapDir + "/" + label + "_" + config.name + "_" + views[k].name + ".png";
        writeHeatmap(path, views[k], m.views[k].testsPerPixel);
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  try {
    std::unique_ptr<RtcLibrary> embree;
    if (o.embree) {
      std::string error;
      embree = RtcLibrary::open(referenceEmbreePath(), "embree", error);
      if (!embree) throw std::runtime_error(error + " (install Debian's libembree-dev, or pass --no-embree)");
    }
    if (!o.heatmapDir.empty()) std::filesystem::create_directories(o.heatmapDir);
    for (const std::string& name : o.presets) {
      const StackPreset& preset = *findStackPreset(name);
      study(generateStack(preset.params, preset.name).asScene(), preset.name, o, embree.get());
    }
    for (const std::string& path : o.meshes) {
      const SceneData scene = obvh::render::loadTriangleScene(path);
      study(scene, std::filesystem::path(path).stem().string(), o, embree.get());
    }
    if (!o.heatmapDir.empty()) std::printf("\nheatmaps (BV tests per pixel, log scale 1..256): %s/\n", o.heatmapDir.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_layouts: %s\n", e.what());
    return 2;
  }
}
