#include "probe_report.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.h"
#include "ladder_workloads.h"
#include "rtc_library.h"
#include "scene_data.h"
#include "trace_timing.h"
#include "triangle_scene_file.h"

namespace obvh::tools {
namespace {

struct ProbeOptions {
  std::string library = "obvh";  // obvh, embree, or a path to a libembree3.so.3
  std::string scene = "/usr/share/glmark2/models/bunny.obj";
  std::string workload = "diffuse";
  int repeat = 10;
  size_t randomRays = 1 << 20;
  std::string config;  // the device config after threads=1
  bool counts = false;  // one more pass, counted: volume tests and leaf visits a ray (obvh, single rays)
};

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_bench probe: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_bench probe [--library obvh|embree|PATH] [--scene FILE] [--workload KEY] [--repeat N]\n"
               "                        [--random-rays N] [--config DEVICE_CONFIG] [--counts on]\n"
               "  Traces one of the ladder's workloads with one library on one thread, N times over (default\n"
               "  10), and prints the best pass in Mrays/s: a steady loop for profilers. The passes run inside\n"
               "  obvh::tools::traceProbeRepeats, so callgrind can count only them, e.g.\n"
               "    valgrind --tool=callgrind --toggle-collect='*traceProbeRepeats*' obvh_bench probe --repeat 1\n"
               "  --workload: primary, random, point, shadow, camera-hint, shadow-hint, diffuse (default),\n"
               "  packets8-hint, packets8-ortho, packets8-slot, streams64-hint (the ladder's rows, the same rays).\n"
               "  --library: obvh (the drop-in built beside this tool, default), embree (Debian's), or the\n"
               "  path of another build's libembree3.so.3.\n"
               "  --config: appended to the device config threads=1 (e.g. intersector=fast).\n"
               "  --counts on: after the timed passes, one pass counted through obvh's traversal statistics\n"
               "  (obvh only; single-ray queries): bounding-volume tests and leaf visits a ray.\n");
  std::exit(error.empty() ? 0 : 2);
}

ProbeOptions parse(int argc, char** argv) {
  ProbeOptions o;
  readFlagValuePairs(argc, argv, usage, [&](const std::string& arg, const std::string& value, auto positive) {
    if (arg == "--library") o.library = value;
    else if (arg == "--scene") o.scene = value;
    else if (arg == "--workload") o.workload = value;
    else if (arg == "--repeat") o.repeat = int(positive(100000));
    else if (arg == "--random-rays") o.randomRays = size_t(positive(100000000));
    else if (arg == "--config") o.config = value;
    else if (arg == "--counts") {
      if (value != "on" && value != "off") usage("--counts takes on or off");
      o.counts = value == "on";
    }
    else usage("unknown option " + arg);
  });
  return o;
}

}  // namespace

// Kept out of line under this name for callgrind's --toggle-collect. Returns the best pass's Mrays/s.
[[gnu::noinline]] double traceProbeRepeats(const RtcLibrary& lib, RTCScene scene, const Workload& workload, int repeat) {
  double best = 0;
  for (int pass = 0; pass < repeat; ++pass)
    best = std::max(best, traceQueryMrays(lib, scene, workload.query, workload.rays, workload.flags));
  return best;
}

// One pass with the calling thread's traversal statistics on (obvh's extension), per ray. The
// statistics count rtcIntersect1 and rtcOccluded1 only.
void printCounts(const RtcLibrary& lib, RTCScene scene, const Workload& workload) {
  if (workload.query != TracedQuery::Intersect1 && workload.query != TracedQuery::Occluded1) {
    std::printf("obvh_bench probe: counted pass: not made (the statistics count rtcIntersect1 and rtcOccluded1 only)\n");
    return;
  }
  lib.obvhEnableTraversalStatistics(1);
  traceQueryMrays(lib, scene, workload.query, workload.rays, workload.flags);
  ObvhTraversalStatistics statistics{};
  lib.obvhTakeTraversalStatistics(&statistics);
  lib.obvhEnableTraversalStatistics(0);
  const double rays = double(workload.rays.size());
  std::printf("obvh_bench probe: counted pass: %.3f bounding-volume tests and %.3f leaf visits a ray\n",
              double(statistics.boundingVolumeTests) / rays, double(statistics.leafVisits) / rays);
}

int runProbeReport(int argc, char** argv) {
  const ProbeOptions options = parse(argc, argv);
  try {
    std::string error;
    auto embree = RtcLibrary::open(referenceEmbreePath(), "embree", error);
    if (!embree) throw std::runtime_error(error + " (install Debian's libembree-dev)");
    std::unique_ptr<RtcLibrary> other;
    const RtcLibrary* lib = embree.get();
    if (options.library != "embree") {
      const std::string path = options.library == "obvh" ? obvhDropInPath() : options.library;
      other = RtcLibrary::open(path, options.library, error);
      if (!other) throw std::runtime_error(error);
      lib = other.get();
    }
    if (options.counts && !lib->obvhEnableTraversalStatistics)
      throw std::runtime_error("--counts: " + lib->label + " has no traversal statistics (not obvh)");
    const SceneData data = obvh::render::loadTriangleScene(options.scene);
    // Embree's scene seeds the secondary rays, as in the ladder.
    RTCDevice embreeDevice = embree->rtcNewDevice("threads=1");
    const std::string config = "threads=1" + (options.config.empty() ? "" : "," + options.config);
    RTCDevice device = lib->rtcNewDevice(config.c_str());
    if (!embreeDevice || !device) throw std::runtime_error("rtcNewDevice(\"" + config + "\") failed");
    double mrays = 0;
    size_t rays = 0;
    {
      const CommittedScene reference(*embree, embreeDevice, data);
      const std::vector<Workload> workloads = ladderWorkloads(*embree, reference.scene(), options.randomRays);
      const auto workload = std::find_if(workloads.begin(), workloads.end(),
                                         [&](const Workload& w) { return options.workload == w.key; });
      if (workload == workloads.end()) usage("unknown workload '" + options.workload + "'");
      const CommittedScene traced(*lib, device, data);
      if (lib->rtcGetDeviceError(device) != RTC_ERROR_NONE)
        throw std::runtime_error(lib->label + ": committing " + data.name + " failed");
      rays = workload->rays.size();
      mrays = traceProbeRepeats(*lib, traced.scene(), *workload, options.repeat);
      if (options.counts) printCounts(*lib, traced.scene(), *workload);
    }
    lib->rtcReleaseDevice(device);
    embree->rtcReleaseDevice(embreeDevice);
    std::printf("obvh_bench probe: %s, %s, %s: %zu rays, best of %d passes %.2f Mrays/s\n", lib->label.c_str(),
                data.name.c_str(), options.workload.c_str(), rays, options.repeat, mrays);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_bench probe: %s\n", e.what());
    return 2;
  }
}

}  // namespace obvh::tools
