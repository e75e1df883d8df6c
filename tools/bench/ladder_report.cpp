#include "ladder_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "build_quality.h"
#include "triangle_scene_file.h"
#include "command_line.h"
#include "ladder_workloads.h"
#include "rtc_library.h"
#include "scene_data.h"
#include "trace_timing.h"

namespace obvh::tools {
namespace {

struct LadderOptions {
  std::vector<std::string> scenes;
  int rounds = 11;
  int threads = 0;
  size_t randomRays = 1 << 20;
  RTCBuildQuality base = RTC_BUILD_QUALITY_MEDIUM, compared = RTC_BUILD_QUALITY_HIGH;
  std::vector<std::string> obvhConfigs;    // --obvh-configs A;B: two obvh devices at the first quality instead
  std::vector<std::string> obvhLibraries;  // --obvh-libraries A;B: two builds of obvh's drop-in instead
};

// "A;B" as its two parts, or an empty list when value is not exactly two parts.
std::vector<std::string> splitPair(const std::string& value) {
  const size_t semicolon = value.find(';');
  if (semicolon == std::string::npos || value.find(';', semicolon + 1) != std::string::npos) return {};
  return {value.substr(0, semicolon), value.substr(semicolon + 1)};
}

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_bench ladder: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_bench ladder [--scene FILE.obj|.ply|.stl|.glb|.gltf]... [--rounds N] [--threads N] [--random-rays N]\n"
               "                         [--qualities low|medium|high,low|medium|high] [--obvh-configs 'A;B']\n"
               "                         [--obvh-libraries 'A.so;B.so']\n"
               "  Builds each scene with Debian's Embree and with obvh at two qualities (default medium,high),\n"
               "  then traces the same rays through all four scenes once per round, in rotating order, and\n"
               "  prints per workload the median Mrays/s and the second quality's speed over the first's:\n"
               "  median of the per-round ratios [lowest, highest], and in how many rounds it was faster.\n"
               "  --obvh-configs: compare two obvh device configs instead (e.g. 'collapse=greedy;collapse=sah'),\n"
               "  both at the first quality, with Embree at that quality as a reference.\n"
               "  --obvh-libraries: compare two builds of obvh's drop-in library (paths to libembree3.so.3 files,\n"
               "  e.g. before and after a change), loaded side by side, likewise.\n"
               "  --threads: build and trace threads of every device (default: all).\n");
  std::exit(error.empty() ? 0 : 2);
}

LadderOptions parse(int argc, char** argv) {
  LadderOptions o;
  readFlagValuePairs(argc, argv, usage, [&](const std::string& arg, const std::string& value, auto positive) {
    if (arg == "--scene") o.scenes.push_back(value);
    else if (arg == "--rounds") o.rounds = int(positive(1000));
    else if (arg == "--threads") o.threads = int(positive(1024));
    else if (arg == "--random-rays") o.randomRays = size_t(positive(100000000));
    else if (arg == "--obvh-configs") {
      o.obvhConfigs = splitPair(value);
      if (o.obvhConfigs.empty())
        usage("invalid value '" + value + "' for --obvh-configs (two device configs separated by one ';')");
    } else if (arg == "--obvh-libraries") {
      o.obvhLibraries = splitPair(value);
      if (o.obvhLibraries.empty())
        usage("invalid value '" + value + "' for --obvh-libraries (two library paths separated by one ';')");
    } else if (arg == "--qualities") {
      const size_t comma = value.find(',');
      if (comma == std::string::npos || !parseBuildQuality(value.substr(0, comma), o.base) ||
          !parseBuildQuality(value.substr(comma + 1), o.compared))
        usage("invalid value '" + value + "' for --qualities (two of low, medium, high, comma-separated)");
    } else {
      usage("unknown option " + arg);
    }
  });
  if (!o.obvhConfigs.empty() && !o.obvhLibraries.empty()) usage("--obvh-configs and --obvh-libraries exclude each other");
  if (o.scenes.empty()) o.scenes.push_back("/usr/share/glmark2/models/bunny.obj");
  return o;
}

const char* qualityName(RTCBuildQuality q) {
  return q == RTC_BUILD_QUALITY_LOW ? "LOW" : q == RTC_BUILD_QUALITY_HIGH ? "HIGH" : "MEDIUM";
}

// A device and the quality its scenes are built at. The ladder's contenders are such pairs; each
// second one is compared with the one before it.
struct DeviceUnderTest {
  std::string label;
  const RtcLibrary* lib;
  RTCDevice device;
  RTCBuildQuality quality;
};

// One contender's scene and its speed per round and workload.
struct Contender {
  DeviceUnderTest d{};
  double buildMs = 0;
  std::unique_ptr<CommittedScene> scene;
  std::vector<std::vector<double>> mrays;  // [workload][round]
};

struct RatioSummary {
  double median = 0, lowest = 0, highest = 0;
  int faster = 0;
};

RatioSummary ratios(const std::vector<double>& compared, const std::vector<double>& base) {
  std::vector<double> r;
  RatioSummary s;
  for (size_t i = 0; i < base.size(); ++i) {
    r.push_back(compared[i] / base[i]);
    s.faster += compared[i] > base[i];
  }
  s.median = median(r);
  s.lowest = *std::min_element(r.begin(), r.end());
  s.highest = *std::max_element(r.begin(), r.end());
  return s;
}

void runScene(const SceneData& scene, const LadderOptions& options, const RtcLibrary& embree,
              const std::vector<DeviceUnderTest>& devices) {
  std::vector<Contender> contenders;
  for (const DeviceUnderTest& d : devices) {
    Contender c;
    c.d = d;
    contenders.push_back(std::move(c));
  }
  for (Contender& c : contenders) {
    { CommittedScene warmUp(*c.d.lib, c.d.device, scene, RTC_SCENE_FLAG_NONE, c.d.quality); }
    c.buildMs = millisecondsOf([&] { c.scene = std::make_unique<CommittedScene>(*c.d.lib, c.d.device, scene, RTC_SCENE_FLAG_NONE, c.d.quality); });
    if (c.d.lib->rtcGetDeviceError(c.d.device) != RTC_ERROR_NONE)
      throw std::runtime_error(c.d.lib->label + ": committing " + scene.name + " failed");
  }

  // Shadow rays and diffuse bounces from Embree's hits of the primary rays at the first quality.
  const Contender& reference = *std::find_if(contenders.begin(), contenders.end(), [&](const Contender& c) { return c.d.lib == &embree; });
  const std::vector<Workload> workloads = ladderWorkloads(embree, reference.scene->scene(), options.randomRays);

  for (Contender& c : contenders) c.mrays.assign(workloads.size(), {});
  for (int round = 0; round < options.rounds; ++round)
    for (size_t w = 0; w < workloads.size(); ++w)
      for (size_t k = 0; k < contenders.size(); ++k) {
        Contender& c = contenders[(k + size_t(round)) % contenders.size()];
        const RTCScene s = c.scene->scene();
        c.mrays[w].push_back(traceQueryMrays(*c.d.lib, s, workloads[w].query, workloads[w].rays, workloads[w].flags));
      }

  std::printf("\n%s, %zu primitives; build ms:", scene.name.c_str(), scene.primitiveCount());
  for (const Contender& c : contenders) std::printf(" %s %.1f;", c.d.label.c_str(), c.buildMs);
  std::printf("\n  %-22s", "Mrays/s (median)");
  for (size_t pair = 0; pair + 1 < contenders.size(); pair += 2)
    std::printf(" %24s %24s  %-29s", contenders[pair].d.label.c_str(), contenders[pair + 1].d.label.c_str(),
                "ratio [lowest, highest] faster");
  if (contenders.size() % 2) std::printf(" %24s", contenders.back().d.label.c_str());
  std::printf("\n");
  for (size_t w = 0; w < workloads.size(); ++w) {
    std::printf("  %-22s", workloads[w].name);
    for (size_t pair = 0; pair + 1 < contenders.size(); pair += 2) {
      const Contender& base = contenders[pair];
      const Contender& compared = contenders[pair + 1];
      const RatioSummary r = ratios(compared.mrays[w], base.mrays[w]);
      char summary[64];
      std::snprintf(summary, sizeof summary, "%.3fx [%.3f, %.3f] %d/%d", r.median, r.lowest, r.highest, r.faster,
                    options.rounds);
      std::printf(" %24.2f %24.2f  %-29s", median(base.mrays[w]), median(compared.mrays[w]), summary);
    }
    if (contenders.size() % 2) std::printf(" %24.2f", median(contenders.back().mrays[w]));
    std::printf("\n");
  }
  std::fflush(stdout);  // a scene's table as soon as it is measured, also when the output is a file
}

}  // namespace

int runLadderReport(int argc, char** argv) {
  const LadderOptions options = parse(argc, argv);
  try {
    std::string error;
    auto embree = RtcLibrary::open(referenceEmbreePath(), "embree", error);
    if (!embree) throw std::runtime_error(error + " (install Debian's libembree-dev)");
    auto obvh = RtcLibrary::open(obvhDropInPath(), "obvh", error);
    if (!obvh) throw std::runtime_error(error + " (build obvh first)");
    const std::string threads = options.threads > 0 ? "threads=" + std::to_string(options.threads) : "";
    std::vector<std::pair<const RtcLibrary*, RTCDevice>> created;
    auto device = [&](const RtcLibrary& lib, const std::string& config) {
      const std::string full = threads + (threads.empty() || config.empty() ? "" : ",") + config;
      RTCDevice d = lib.rtcNewDevice(full.c_str());
      if (!d) throw std::runtime_error(lib.label + ": rtcNewDevice(\"" + full + "\") failed");
      created.push_back({&lib, d});
      return d;
    };
    const std::string base = qualityName(options.base), compared = qualityName(options.compared);
    std::vector<DeviceUnderTest> devices;
    std::unique_ptr<RtcLibrary> builds[2];
    if (!options.obvhLibraries.empty()) {
      for (int k = 0; k < 2; ++k) {
        builds[k] = RtcLibrary::open(options.obvhLibraries[k], "obvh " + options.obvhLibraries[k], error);
        if (!builds[k]) throw std::runtime_error(error);
      }
      devices = {{builds[0]->label, builds[0].get(), device(*builds[0], ""), options.base},
                 {builds[1]->label, builds[1].get(), device(*builds[1], ""), options.base},
                 {"embree " + base, embree.get(), device(*embree, ""), options.base}};
      std::printf("obvh_bench ladder: %s vs %s at %s", options.obvhLibraries[0].c_str(), options.obvhLibraries[1].c_str(),
                  base.c_str());
    } else if (options.obvhConfigs.empty()) {
      RTCDevice e = device(*embree, ""), o = device(*obvh, "");
      devices = {{"embree " + base, embree.get(), e, options.base}, {"embree " + compared, embree.get(), e, options.compared},
                 {"obvh " + base, obvh.get(), o, options.base}, {"obvh " + compared, obvh.get(), o, options.compared}};
      std::printf("obvh_bench ladder: %s vs %s", base.c_str(), compared.c_str());
    } else {
      devices = {{"obvh " + options.obvhConfigs[0], obvh.get(), device(*obvh, options.obvhConfigs[0]), options.base},
                 {"obvh " + options.obvhConfigs[1], obvh.get(), device(*obvh, options.obvhConfigs[1]), options.base},
                 {"embree " + base, embree.get(), device(*embree, ""), options.base}};
      std::printf("obvh_bench ladder: obvh '%s' vs '%s' at %s", options.obvhConfigs[0].c_str(),
                  options.obvhConfigs[1].c_str(), base.c_str());
    }
    std::printf(", %d rounds, %s threads; per round every scene traces every workload once\n", options.rounds,
                options.threads > 0 ? std::to_string(options.threads).c_str() : "all");
    for (const std::string& path : options.scenes) runScene(obvh::render::loadTriangleScene(path), options, *embree, devices);
    for (auto [lib, d] : created) lib->rtcReleaseDevice(d);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_bench ladder: %s\n", e.what());
    return 2;
  }
}

}  // namespace obvh::tools
