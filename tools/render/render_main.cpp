// obvh_render: renders a glTF 2.0 scene (or an OBJ/PLY mesh) through the Embree 3 C API of a
// library chosen at run time (obvh's drop-in, Debian's Embree, or whatever libembree3.so.3 the
// loader finds), simulating only the effects the scene calls for.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include "committed_scene.h"
#include "effects.h"
#include "build_quality.h"
#include "frame_output.h"
#include "heatmap.h"
#include "integrator.h"
#include "renderer.h"
#include "rtc_library.h"
#include "scene_loader.h"
#include "view_camera.h"

using namespace obvh;
using namespace obvh::render;

namespace {

struct Options {
  std::string scene, output = "render.png", library = "obvh";
  FrameSettings frame;
  int spp = 0;  // 0: 1 without path tracing, 16 with
  int maxDepth = 8;
  size_t camera = 0;
  Projection projection = Projection::FromScene;
  float time = 0.f, exposure = 0.f;
  int frames = 1;
  std::set<Effect> disabled;
  bool quiet = false;
  std::string heatmap;
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;
};

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_render: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_render SCENE.gltf|.glb|.obj|.ply|.stl [-o OUT.png|.exr] [options]\n"
               "  --library obvh|embree|system|PATH  which Embree 3 library traces the rays (default obvh;\n"
               "                                     system: the libembree3.so.3 that LD_LIBRARY_PATH finds)\n"
               "  --width W --height H               image size (default 640 x 480)\n"
               "  --spp N                            samples per pixel (default 1; 16 path tracing; 64 dispersion)\n"
               "  --max-depth N                      path vertices (default 8)\n"
               "  --camera N                         the scene's N-th camera (default 0)\n"
               "  --orthographic | --perspective     ignore the scene's cameras, frame the scene automatically\n"
               "  --time T                           seconds into the scene's animation (default 0)\n"
               "  --frames N                         render N frames over the animation: OUT_0000.png ...\n"
               "  --exposure EV                      stops applied before display encoding (default 0)\n"
               "  --disable E1,E2                    turn off effects: shadows, transparency, path-tracing,\n"
               "                                     dispersion, animation\n"
               "  --heatmap FILE.png                 also write bounding-volume tests per pixel (log scale 1..256;\n"
               "                                     obvh only: Embree does not count them)\n"
               "  --quality low|medium|high          rtcSetSceneBuildQuality of a static scene (default medium)\n"
               "  --quiet                            no progress bar\n");
  std::exit(error.empty() ? 0 : 2);
}

double number(const std::string& flag, const char* value, double lo, double hi) {
  char* end = nullptr;
  const double v = std::strtod(value, &end);
  if (*value == '\0' || *end != '\0' || !(v >= lo && v <= hi)) {
    std::ostringstream bounds;
    bounds << "invalid value '" << value << "' for " << flag << " (expected " << lo << " .. " << hi << ")";
    usage(bounds.str());
  }
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage("");
    const bool flag = arg == "--orthographic" || arg == "--perspective" || arg == "--quiet";
    if (arg.rfind("-", 0) == 0 && !flag && i + 1 >= argc) usage(arg + " needs a value");
    if (arg == "-o" || arg == "--output") o.output = argv[++i];
    else if (arg == "--library") o.library = argv[++i];
    else if (arg == "--heatmap") o.heatmap = argv[++i];
    else if (arg == "--quality") {
      const std::string level = argv[++i];
      if (!tools::parseBuildQuality(level, o.quality)) usage("--quality takes low, medium or high, not '" + level + "'");
    }
    else if (arg == "--width") o.frame.width = int(number(arg, argv[++i], 1, 16384));
    else if (arg == "--height") o.frame.height = int(number(arg, argv[++i], 1, 16384));
    else if (arg == "--spp") o.spp = int(number(arg, argv[++i], 1, 65536));
    else if (arg == "--max-depth") o.maxDepth = int(number(arg, argv[++i], 1, 1024));
    else if (arg == "--camera") o.camera = size_t(number(arg, argv[++i], 0, 1e6));
    else if (arg == "--time") o.time = float(number(arg, argv[++i], 0, 1e9));
    else if (arg == "--frames") o.frames = int(number(arg, argv[++i], 1, 100000));
    else if (arg == "--exposure") o.exposure = float(number(arg, argv[++i], -30, 30));
    else if (arg == "--orthographic") o.projection = Projection::Orthographic;
    else if (arg == "--perspective") o.projection = Projection::Perspective;
    else if (arg == "--quiet") o.quiet = true;
    else if (arg == "--disable") {
      std::stringstream list(argv[++i]);
      for (std::string name; std::getline(list, name, ',');) {
        try {
          o.disabled.insert(parseEffect(name));
        } catch (const std::exception& e) {
          usage(e.what());
        }
      }
    } else if (arg.rfind("-", 0) == 0) usage("unknown option " + arg);
    else if (o.scene.empty()) o.scene = arg;
    else usage("more than one scene given ('" + o.scene + "' and '" + arg + "')");
  }
  if (o.scene.empty()) usage("no scene given");
  return o;
}

std::string libraryPath(const std::string& choice) {
  if (choice == "obvh") return tools::obvhDropInPath();
  if (choice == "embree") return tools::referenceEmbreePath();
  if (choice == "system") return "libembree3.so.3";
  return choice;
}

// OUT.png -> OUT_0007.png for frame 7 of an animation.
std::string framePath(const std::string& output, int frame, int frames) {
  if (frames == 1) return output;
  const size_t dot = output.find_last_of('.');
  char number[16];
  std::snprintf(number, sizeof number, "_%04d", frame);
  return dot == std::string::npos ? output + number : output.substr(0, dot) + number + output.substr(dot);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void reportDeviceError(void* label, RTCError code, const char* message) {
  std::fprintf(stderr, "obvh_render: %s reports error %d: %s\n", static_cast<const char*>(label), int(code), message);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  try {
    auto start = std::chrono::steady_clock::now();
    const RenderScene scene = loadRenderScene(o.scene);
    const double loadSeconds = secondsSince(start);
    for (const std::string& warning : scene.warnings) std::fprintf(stderr, "obvh_render: note: %s\n", warning.c_str());

    std::string error;
    auto lib = tools::RtcLibrary::open(libraryPath(o.library), o.library, error);
    if (!lib) throw std::runtime_error("cannot load library '" + o.library + "': " + error);
    RTCDevice device = lib->rtcNewDevice(nullptr);
    if (!device) throw std::runtime_error(o.library + ": rtcNewDevice failed");
    lib->rtcSetDeviceErrorFunction(device, reportDeviceError, const_cast<char*>(lib->label.c_str()));

    ScenePose pose = poseAt(scene, o.time);
    const EffectPlan plan = planEffects(scene, pose, o.disabled);
    const bool animate = plan.animation && o.frames > 1;
    std::printf("scene: %s, %zu triangles, %zu placed meshes, %zu lights, %zu cameras; library %s\n", scene.name.c_str(),
                scene.triangleCount(), pose.meshes.size(), pose.lights.size(), pose.cameras.size(), lib->path.c_str());
    std::printf("%s\n", plan.summary.c_str());
    if (o.frames > 1 && !plan.animation) std::printf("note: --frames %d on a scene without animation renders one frame\n", o.frames);

    start = std::chrono::steady_clock::now();
    auto committed = std::make_unique<CommittedRenderScene>(*lib, device, scene, pose, animate, o.quality);
    const double buildSeconds = secondsSince(start);
    if (lib->rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error(o.library + " failed to build the scene");

    FrameSettings frame = o.frame;
    frame.samplesPerPixel = o.spp > 0 ? o.spp : (plan.dispersion ? 64 : plan.pathTracing ? 16 : 1);
    frame.progress = !o.quiet;
    frame.heatmap = !o.heatmap.empty();
    IntegratorSettings settings;
    settings.maxDepth = o.maxDepth;
    std::string cameraDescription;
    const int frames = animate ? o.frames : 1;
    const float duration = scene.animationDuration();
    double renderSeconds = 0.0, updateSeconds = 0.0;
    uint64_t rays = 0;
    for (int f = 0; f < frames; ++f) {
      if (animate) {
        const float time = o.time + duration * float(f) / float(frames - 1);
        pose = poseAt(scene, time);
        if (f > 0) {
          start = std::chrono::steady_clock::now();
          committed->update(pose);
          updateSeconds += secondsSince(start);
        }
        frame.frame = uint64_t(f);
      }
      const ViewCamera camera = chooseCamera(scene, pose, o.camera, o.projection, frame.width, frame.height, cameraDescription);
      if (f == 0) std::printf("camera: %s; %dx%d, %d spp\n", cameraDescription.c_str(), frame.width, frame.height, frame.samplesPerPixel);
      const Integrator integrator(*lib, *committed, scene, pose, plan, settings);
      const Frame image = renderFrame(integrator, camera, frame);
      renderSeconds += image.seconds;
      rays += image.rays;
      const std::string path = framePath(o.output, f, frames);
      if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty()) std::filesystem::create_directories(parent);
      writeFrame(path, image, o.exposure);
      if (frame.heatmap) {
        const std::string heatPath = framePath(o.heatmap, f, frames);
        tools::writeHeatmap(heatPath, image.width, image.height, image.volumeTests);
        double total = 0.0;
        for (float v : image.volumeTests) total += v;
        std::printf("heatmap: %s, %.1f bounding-volume tests per pixel on average\n", heatPath.c_str(),
                    total / double(image.volumeTests.size()));
      }
      if (frames == 1 || f == frames - 1) std::printf("wrote %s%s\n", path.c_str(), frames > 1 ? " (and the frames before it)" : "");
    }
    std::printf("time: load %.1f ms, build %.1f ms%s, render %.2f s (%d frame%s), %.2f Mrays/s (%llu rays)\n",
                1e3 * loadSeconds, 1e3 * buildSeconds,
                animate ? (", per-frame update " + std::to_string(1e3 * updateSeconds / (frames - 1)).substr(0, 6) + " ms").c_str() : "",
                renderSeconds, frames, frames == 1 ? "" : "s", renderSeconds > 0 ? 1e-6 * double(rays) / renderSeconds : 0.0,
                static_cast<unsigned long long>(rays));
    committed.reset();  // scenes go before their device
    lib->rtcReleaseDevice(device);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_render: %s\n", e.what());
    return 1;
  }
  return 0;
}
