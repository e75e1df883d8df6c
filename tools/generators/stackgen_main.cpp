// obvh_stackgen: writes a semiconductor-stack scene (a preset, or parameters) as OBJ or glTF.
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scene_writer.h"
#include "stack_generator.h"

using namespace obvh::tools;

namespace {

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_stackgen: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_stackgen (--preset NAME | [parameters]) --out FILE.obj|FILE.gltf|FILE.glb\n"
               "       obvh_stackgen --list\n"
               "parameters: --layers N --angles A,B,... (degrees) --pitch P --width-ratio R --die SIZE\n"
               "            --vias N (per layer) --steps N (stepped profiles) --blocks N --seed S\n"
               "            --triangles N (solve the pitch for about N triangles)\n");
  std::exit(error.empty() ? 0 : 2);
}

double number(const std::string& flag, const std::string& value, double lo, double hi) {
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(v >= lo && v <= hi))
    usage("invalid value '" + value + "' for " + flag + " (expected " + std::to_string(lo) + " .. " +
          std::to_string(hi) + ")");
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  StackParams params;
  std::string out, name = "stack";
  bool presetChosen = false, parametersGiven = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage("");
    if (arg == "--list") {
      for (const StackPreset& p : stackPresets()) {
        const StackScene s = generateStack(p.params, p.name);
        std::printf("%-14s %9zu triangles (target %zu)  %s\n", p.name.c_str(), s.triangleCount(),
                    p.params.targetTriangles, p.description.c_str());
      }
      return 0;
    }
    if (i + 1 >= argc) usage("missing value for " + arg);
    const std::string value = argv[++i];
    if (arg == "--out") { out = value; continue; }
    if (arg == "--preset") {
      const StackPreset* p = findStackPreset(value);
      if (!p) usage("unknown preset '" + value + "' (see --list)");
      params = p->params, name = p->name, presetChosen = true;
      continue;
    }
    parametersGiven = true;
    if (arg == "--layers") params.layers = int(number(arg, value, 1, 1000));
    else if (arg == "--pitch") params.linePitch = float(number(arg, value, 1e-3, 1e6));
    else if (arg == "--width-ratio") params.lineWidthRatio = float(number(arg, value, 0.01, 0.99));
    else if (arg == "--die") params.dieSize = float(number(arg, value, 1e-3, 1e6));
    else if (arg == "--vias") params.viasPerLayer = int(number(arg, value, 0, 1e6));
    else if (arg == "--steps") params.steppedProfiles = int(number(arg, value, 0, 1e5));
    else if (arg == "--blocks") params.blocks = int(number(arg, value, 0, 1e6));
    else if (arg == "--seed") params.seed = uint32_t(number(arg, value, 0, 4294967295.0));
    else if (arg == "--triangles") params.targetTriangles = size_t(number(arg, value, 1, 1e9));
    else if (arg == "--angles") {
      params.angles.clear();
      std::stringstream list(value);
      std::string item;
      while (std::getline(list, item, ',')) params.angles.push_back(float(number(arg, item, -360, 360)));
      if (params.angles.empty()) usage("--angles needs at least one angle");
    } else {
      usage("unknown option " + arg);
    }
  }
  if (presetChosen && parametersGiven) usage("give either --preset or parameters, not both");
  if (out.empty()) usage("missing --out FILE");
  try {
    const StackScene scene = generateStack(params, name);
    writeStackScene(scene, out);
    std::printf("obvh_stackgen: wrote %s (%zu triangles)\n", out.c_str(), scene.triangleCount());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_stackgen: %s\n", e.what());
    return 1;
  }
}
