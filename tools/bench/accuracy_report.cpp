#include "accuracy_report.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "accuracy_study.h"
#include "triangle_scene_file.h"
#include "command_line.h"
#include "ray_generation.h"
#include "rtc_library.h"
#include "scene_data.h"
#include "trace_timing.h"

namespace obvh::tools {
namespace {

struct ReportOptions {
  std::vector<std::string> scenes;
  int runs = 5;
  size_t raysPerCase = 50000;
  std::string outDir = "out";
};

[[noreturn]] void usage(const std::string& error) {
  if (!error.empty()) std::fprintf(stderr, "obvh_bench accuracy: %s\n\n", error.c_str());
  std::fprintf(stderr,
               "usage: obvh_bench accuracy [--scene FILE.obj|.ply|.stl|.glb|.gltf]... [--runs N] [--rays-per-case N] [--out DIR]\n"
               "  Per accuracy mode of obvh and of Debian's Embree: Mrays/s on each scene (default: the bunny)\n"
               "  and the error rates of the accuracy study; writes DIR/accuracy.csv and DIR/accuracy.png.\n");
  std::exit(error.empty() ? 0 : 2);
}

ReportOptions parse(int argc, char** argv) {
  ReportOptions o;
  readFlagValuePairs(argc, argv, usage, [&](const std::string& arg, const std::string& value, auto positive) {
    if (arg == "--scene") o.scenes.push_back(value);
    else if (arg == "--runs") o.runs = int(positive(1000));
    else if (arg == "--rays-per-case") o.raysPerCase = size_t(positive(100000000));
    else if (arg == "--out") o.outDir = value;
    else usage("unknown option " + arg);
  });
  if (o.scenes.empty()) o.scenes.push_back("/usr/share/glmark2/models/bunny.obj");
  return o;
}

struct SpeedRow {
  double primaryMrays = 0, randomMrays = 0;
};

struct ModeRow {
  std::string mode;
  std::vector<SpeedRow> speeds;  // per scene
  size_t closedRays = 0, leaks = 0, doubleReports = 0;
  double maxClosedTErrorUlps = 0;
  size_t grazingRays = 0, grazingFalse = 0, grazingMissed = 0;
};

SpeedRow measureSpeed(const AccuracyMode& mode, const SceneData& scene, int runs) {
  const RtcLibrary& lib = *mode.lib;
  RTCDevice device = lib.rtcNewDevice(mode.config.empty() ? nullptr : mode.config.c_str());
  if (!device) throw std::runtime_error(mode.name + ": rtcNewDevice failed");
  SpeedRow row;
  {
    const CommittedScene committed(lib, device, scene, mode.flags);
    RTCBounds b;
    lib.rtcGetSceneBounds(committed.scene(), &b);
    const SceneBox box{{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
    row.primaryMrays = traceIntersectMrays(lib, committed.scene(), perspectiveRays(box, 1024, 768), runs);
    row.randomMrays = traceIntersectMrays(lib, committed.scene(), randomRays(box, 1 << 20, 12345u), runs);
  }
  lib.rtcReleaseDevice(device);
  return row;
}

double perMillion(size_t count, size_t total) { return total ? 1e6 * double(count) / double(total) : 0.0; }

void writeCsv(const std::string& path, const std::vector<SceneData>& scenes, const std::vector<ModeRow>& rows) {
  std::ofstream csv(path);
  if (!csv) throw std::runtime_error("cannot write " + path);
  // Error columns first so that the plot script finds the first scene's speed at fixed columns.
  csv << "mode,closed-mesh rays,leaks per million,double reports per million,max t error ulps (closed),"
         "grazing rays,grazing false hits,grazing missed hits";
  for (const SceneData& s : scenes) csv << "," << s.name << " primary Mrays/s," << s.name << " random Mrays/s";
  csv << "\n";
  for (const ModeRow& r : rows) {
    csv << '"' << r.mode << '"' << "," << r.closedRays << "," << perMillion(r.leaks, r.closedRays) << ","
        << perMillion(r.doubleReports, r.closedRays) << "," << r.maxClosedTErrorUlps << "," << r.grazingRays << ","
        << r.grazingFalse << "," << r.grazingMissed;
    for (const SpeedRow& s : r.speeds) csv << "," << s.primaryMrays << "," << s.randomMrays;
    csv << "\n";
  }
}

bool plot(const std::string& csv, const std::string& png) {
  const std::string command = "gnuplot -e \"csv='" + csv + "'; png='" + png + "'\" '" OBVH_ACCURACY_PLOT_SCRIPT "'";
  return std::system(command.c_str()) == 0;
}

}  // namespace

int runAccuracyReport(int argc, char** argv) {
  const ReportOptions options = parse(argc, argv);
  try {
    std::vector<SceneData> scenes;
    for (const std::string& path : options.scenes) scenes.push_back(obvh::render::loadTriangleScene(path));
    std::string error;
    auto embree = RtcLibrary::open(referenceEmbreePath(), "embree", error);
    if (!embree) throw std::runtime_error(error + " (install Debian's libembree-dev)");
    auto obvh = RtcLibrary::open(obvhDropInPath(), "obvh", error);
    if (!obvh) throw std::runtime_error(error + " (build obvh first)");

    std::vector<HardCase> cases = closedMeshCases(options.raysPerCase, 7);
    cases.push_back(grazingSkinnyCase(200, 2 * options.raysPerCase, 8));

    std::vector<ModeRow> rows;
    for (const AccuracyMode& mode : standardModes(*embree, *obvh)) {
      ModeRow row;
      row.mode = mode.name;
      for (const SceneData& scene : scenes) row.speeds.push_back(measureSpeed(mode, scene, options.runs));
      for (const HardCase& c : cases) {
        const CaseResult r = runCase(mode, c);
        if (r.kind == CaseKind::ClosedConvex) {
          row.closedRays += r.rays, row.leaks += r.missed, row.doubleReports += r.doubleReports;
          row.maxClosedTErrorUlps = std::max(row.maxClosedTErrorUlps, r.maxTErrorUlps);
        } else {
          row.grazingRays += r.rays, row.grazingFalse += r.falseHits, row.grazingMissed += r.missed;
        }
      }
      rows.push_back(row);
    }

    std::printf("obvh_bench accuracy: medians of %d runs; closed meshes: %zu rays per mode at shared edges and "
                "vertices; grazing: %zu rays at skinny triangles\n",
                options.runs, rows[0].closedRays, rows[0].grazingRays);
    for (size_t s = 0; s < scenes.size(); ++s)
      std::printf("  speed on %s (%zu primitives), ratio to embree default in brackets\n", scenes[s].name.c_str(),
                  scenes[s].primitiveCount());
    std::printf("  %-17s", "mode");
    for (const SceneData& s : scenes) std::printf(" %20s %20s", (s.name + " prim.").c_str(), (s.name + " random").c_str());
    std::printf(" %9s %9s %9s %8s %8s\n", "leaks/M", "double/M", "t err ulp", "grz false", "grz miss");
    const ModeRow* embreeDefault = nullptr;
    for (const ModeRow& r : rows)
      if (r.mode == "embree default") embreeDefault = &r;
    for (const ModeRow& r : rows) {
      std::printf("  %-17s", r.mode.c_str());
      for (size_t s = 0; s < r.speeds.size(); ++s) {
        const SpeedRow& base = embreeDefault->speeds[s];
        std::printf("   %7.2f (%5.2fx)   %7.2f (%5.2fx)", r.speeds[s].primaryMrays,
                    r.speeds[s].primaryMrays / base.primaryMrays, r.speeds[s].randomMrays,
                    r.speeds[s].randomMrays / base.randomMrays);
      }
      std::printf(" %9.1f %9.0f %9.2f %8zu %8zu\n", perMillion(r.leaks, r.closedRays),
                  perMillion(r.doubleReports, r.closedRays), r.maxClosedTErrorUlps, r.grazingFalse, r.grazingMissed);
    }

    std::filesystem::create_directories(options.outDir);
    const std::string csv = options.outDir + "/accuracy.csv", png = options.outDir + "/accuracy.png";
    writeCsv(csv, scenes, rows);
    if (plot(csv, png)) {
      std::printf("wrote %s and %s\n", csv.c_str(), png.c_str());
    } else {
      std::printf("wrote %s; plotting %s failed (is gnuplot installed? Debian package gnuplot-nox)\n", csv.c_str(),
                  png.c_str());
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_bench accuracy: %s\n", e.what());
    return 2;
  }
}

}  // namespace obvh::tools
