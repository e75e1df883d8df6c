// obvh_bench: commits one scene to Debian's Embree and to obvh in the same process, traces the same
// rays through both, prints build time, Mrays/s (medians) and how many answers differ, and writes
// both libraries' images.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <tbb/parallel_for.h>

#include "accuracy_report.h"
#include "ladder_report.h"
#include "probe_report.h"
#include "build_quality.h"
#include "build_statistics.h"
#include "hit_compare.h"
#include "image_io.h"
#include "triangle_scene_file.h"
#include "command_line.h"
#include "ray_generation.h"
#include "rtc_library.h"
#include "scene_data.h"
#include "scene_memory.h"
#include "trace_timing.h"

using namespace obvh::tools;

namespace {

constexpr const char* kDefaultScenePath = "/usr/share/glmark2/models/bunny.obj";

struct Options {
  std::string scene = kDefaultScenePath;
  int width = 1024;
  int height = 768;
  int runs = 5;
  size_t randomRays = 1 << 20;
  std::string outDir = "out";
  RTCBuildQuality quality = RTC_BUILD_QUALITY_MEDIUM;  // of the scene every workload traces
  int threads = 0;  // build and trace threads of every device (0: all)
  bool hasSource = false;  // --source: where the point-source rays start (default: the scene's centre)
  float source[3] = {0.f, 0.f, 0.f};
};

[[noreturn]] void usage(const char* error) {
  if (error) std::fprintf(stderr, "obvh_bench: %s\n\n", error);
  std::fprintf(stderr,
               "usage: obvh_bench [--scene FILE.obj|.ply|.stl|.glb|.gltf] [--width W] [--height H] [--runs N] [--random-rays N] "
               "[--out DIR] [--quality low|medium|high] [--threads N] [--source X,Y,Z]\n"
               "       obvh_bench accuracy --help   (what each accuracy mode costs in time)\n"
               "       obvh_bench ladder --help     (what a build quality buys in trace speed)\n"
               "       obvh_bench probe --help      (one workload, one library, a loop for profilers)\n"
               "  Traces the scene with Debian's Embree and with obvh in one run and compares them.\n"
               "  --source: start of the point-source (transmitter) rays; default: the centre of the scene.\n"
               "  obvh's devices also take OBVH_CONFIG, e.g. OBVH_CONFIG=builder=kmeans.\n"
               "  default scene: %s (Debian package glmark2-data)\n",
               kDefaultScenePath);
  std::exit(error ? 2 : 0);
}

long parsePositive(const char* flag, const char* value, long maxValue) {
  const std::optional<long> v = parsePositiveNumber(value, maxValue);
  if (!v) usage((std::string("invalid value '") + value + "' for " + flag).c_str());
  return *v;
}

Options parseOptions(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") usage(nullptr);
    if (i + 1 >= argc) usage(("missing value for " + arg).c_str());
    const char* value = argv[++i];
    if (arg == "--scene") o.scene = value;
    else if (arg == "--width") o.width = int(parsePositive("--width", value, 16384));
    else if (arg == "--height") o.height = int(parsePositive("--height", value, 16384));
    else if (arg == "--runs") o.runs = int(parsePositive("--runs", value, 1000));
    else if (arg == "--random-rays") o.randomRays = size_t(parsePositive("--random-rays", value, 1L << 28));
    else if (arg == "--out") o.outDir = value;
    else if (arg == "--threads") o.threads = int(parsePositive("--threads", value, 1024));
    else if (arg == "--source") {
      char extra = 0;
      if (std::sscanf(value, "%f,%f,%f%c", &o.source[0], &o.source[1], &o.source[2], &extra) != 3)
        usage(("--source takes X,Y,Z, not " + std::string(value)).c_str());
      o.hasSource = true;
    }
    else if (arg == "--quality") {
      if (!parseBuildQuality(value, o.quality))
        usage(("--quality takes low, medium or high, not " + std::string(value)).c_str());
    }
    else usage(("unknown option " + arg).c_str());
  }
  return o;
}

// One row of the table: a ray set traced through one query API, with the intersect context's
// coherence hint an application would give it (Embree's documentation: primary visibility and hard
// shadows are coherent workloads; rtcInitIntersectContext's default says incoherent).
struct Workload {
  const char* name;
  TracedQuery query;
  const std::vector<RTCRay>* rays;
  RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
};
constexpr RTCIntersectContextFlags kCoherent = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;

struct Result {
  double mrays = 0;
  std::vector<RTCRayHit> hits;  // intersect queries
  std::vector<RTCRay> rays;     // occlusion queries (tfar = -inf: occluded)
};

struct LibraryRun {
  const RtcLibrary* lib = nullptr;
  std::string config;            // rtcNewDevice config
  bool defaultMode = true;       // obvh's default triangle test (must agree with Embree)
  const char* name = "";
  RTCDevice device = nullptr;
  std::unique_ptr<CommittedScene> scene;
  double buildMs = 0;
  double refitMs = 0;
  double lowBuildMs = 0;
  double sah = 0;               // as the library's verbose=2 statistics report it
  SceneMemory memory;           // of the traced scene's build quality
  std::vector<Result> results;  // one per workload, in table order
};

// A scene whose geometries ask for RTC_BUILD_QUALITY_REFIT, committed again after every vertex
// moved (a small shear); returns the median time of such a commit (vertex copy included).
double refitMilliseconds(const RtcLibrary& lib, RTCDevice device, const SceneData& scene, int runs) {
  SceneData moved = scene;
  CommittedScene committed(lib, device, moved);
  for (size_t id = 0; id < moved.meshes.size(); ++id)
    lib.rtcSetGeometryBuildQuality(committed.geometry(unsigned(id)), RTC_BUILD_QUALITY_REFIT);
  committed.recommit(moved);
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    for (MeshData& mesh : moved.meshes)
      for (size_t i = 0; i + 2 < mesh.vertices.size(); i += 3) mesh.vertices[i] += 1e-3f * mesh.vertices[i + 1];
    times.push_back(millisecondsOf([&] { committed.recommit(moved); }));
  }
  return median(times);
}

// One timed pass of the workload; its answers go to r when r is given. Returns Mrays/s.
double tracePass(const LibraryRun& run, const Workload& w, Result* r) {
  return traceQueryMrays(*run.lib, run.scene->scene(), w.query, *w.rays, w.contextFlags, r ? &r->hits : nullptr,
                         r ? &r->rays : nullptr);
}

// The libraries take turns, pass by pass, so that the shared machine's slow and fast spells fall
// on all of them alike rather than on whichever ran its passes in that spell; each library's row
// is the median of its passes, its answers the first pass's.
template <size_t kRuns>
void traceInTurns(LibraryRun (&runs)[kRuns], const Workload& w, int passes) {
  std::vector<double> rates[kRuns];
  Result results[kRuns];
  for (int pass = 0; pass < passes; ++pass)
    for (size_t i = 0; i < kRuns; ++i) rates[i].push_back(tracePass(runs[i], w, pass == 0 ? &results[i] : nullptr));
  for (size_t i = 0; i < kRuns; ++i) {
    results[i].mrays = median(rates[i]);
    runs[i].results.push_back(std::move(results[i]));
  }
}

struct MismatchCount {
  size_t rays = 0, differing = 0, ambiguous = 0, mismatched = 0;
  std::string firstMismatch;

  void add(const Comparison& c, const RTCRay& ray) {
    if (c.verdict == Verdict::Equal) return;
    ++differing;
    if (c.verdict == Verdict::Ambiguous) {
      ++ambiguous;
    } else {
      ++mismatched;
      if (firstMismatch.empty()) firstMismatch = describeRay(ray) + ": " + c.reason;
    }
  }
};

MismatchCount compareIntersections(const SceneData& scene, const std::vector<RTCRay>& rays,
                                   const std::vector<RTCRayHit>& reference, const std::vector<RTCRayHit>& candidate) {
  MismatchCount count;
  count.rays = rays.size();
  for (size_t i = 0; i < rays.size(); ++i)
    count.add(compareHits(scene, rays[i], toHitRecord(reference[i]), toHitRecord(candidate[i])), rays[i]);
  return count;
}

// Differing occlusion answers are judged like differing hits: by hit_compare's brute-force
// double-precision test (every primitive of the scene), made once per ray for all the rows that
// trace the same rays, and in parallel.
class OcclusionJudge {
 public:
  explicit OcclusionJudge(const SceneData& scene) : scene_(scene) {}

  MismatchCount compare(const std::vector<RTCRay>& rays, const std::vector<RTCRay>& reference,
                        const std::vector<RTCRay>& candidate) {
    const auto occluded = [](const RTCRay& r) { return r.tfar == -std::numeric_limits<float>::infinity(); };
    std::vector<int8_t>& truths = truths_[&rays];
    truths.resize(rays.size(), kUnknown);
    std::vector<size_t> differing, unjudged;
    for (size_t i = 0; i < rays.size(); ++i) {
      if (occluded(reference[i]) == occluded(candidate[i])) continue;
      differing.push_back(i);
      if (truths[i] == kUnknown) unjudged.push_back(i);
    }
    tbb::parallel_for(size_t(0), unjudged.size(), [&](size_t k) {
      truths[unjudged[k]] = int8_t(exactOcclusion(scene_, rays[unjudged[k]]));
    });
    MismatchCount count;
    count.rays = rays.size();
    for (size_t i : differing)
      count.add(judgeOcclusion(OcclusionTruth(truths[i]), occluded(reference[i]), occluded(candidate[i])), rays[i]);
    return count;
  }

 private:
  static constexpr int8_t kUnknown = -1;
  const SceneData& scene_;
  std::map<const std::vector<RTCRay>*, std::vector<int8_t>> truths_;
};

std::vector<float> shade(const std::vector<RTCRayHit>& hits, const std::vector<RTCRay>& shadow) {
  std::vector<float> rgb(hits.size() * 3);
  for (size_t i = 0; i < hits.size(); ++i) {
    const RTCRayHit& h = hits[i];
    float c[3] = {0.08f, 0.1f, 0.16f};
    if (h.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      const float nl = std::sqrt(h.hit.Ng_x * h.hit.Ng_x + h.hit.Ng_y * h.hit.Ng_y + h.hit.Ng_z * h.hit.Ng_z);
      const float dl = std::sqrt(h.ray.dir_x * h.ray.dir_x + h.ray.dir_y * h.ray.dir_y + h.ray.dir_z * h.ray.dir_z);
      const float cosine = std::fabs(h.hit.Ng_x * h.ray.dir_x + h.hit.Ng_y * h.ray.dir_y + h.hit.Ng_z * h.ray.dir_z) /
                           std::max(nl * dl, 1e-30f);
      const bool inShadow = shadow[i].tfar == -std::numeric_limits<float>::infinity();
      const float value = (0.15f + 0.85f * cosine) * (inShadow ? 0.45f : 1.f);
      c[0] = c[1] = c[2] = value;
    }
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = c[k];
  }
  return rgb;
}

void printRow(const char* name, double embree, double obvh, double fast, bool lowerIsBetter) {
  const double speed = lowerIsBetter ? embree / obvh : obvh / embree;
  const double fastSpeed = lowerIsBetter ? embree / fast : fast / embree;
  std::printf("  %-56s %10.2f %10.2f %9.2fx %10.2f %9.2fx\n", name, embree, obvh, speed, fast, fastSpeed);
}

void printCount(const char* name, const MismatchCount& c) {
  std::printf("  %-56s %9zu rays: %zu differ, %zu ambiguous (proved in double precision), %zu mismatches\n", name,
              c.rays, c.differing, c.ambiguous, c.mismatched);
  if (!c.firstMismatch.empty()) std::printf("    first mismatch: %s\n", c.firstMismatch.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::strcmp(argv[1], "accuracy") == 0) return runAccuracyReport(argc - 1, argv + 1);
  if (argc > 1 && std::strcmp(argv[1], "ladder") == 0) return runLadderReport(argc - 1, argv + 1);
  if (argc > 1 && std::strcmp(argv[1], "probe") == 0) return runProbeReport(argc - 1, argv + 1);
  const Options options = parseOptions(argc, argv);
  try {
    const SceneData scene = obvh::render::loadTriangleScene(options.scene);
    std::string error;
    auto embree = RtcLibrary::open(referenceEmbreePath(), "embree", error);
    if (!embree) throw std::runtime_error(error + " (install Debian's libembree-dev)");
    auto obvh = RtcLibrary::open(obvhDropInPath(), "obvh", error);
    if (!obvh) throw std::runtime_error(error + " (build obvh first)");

    // Embree's default, obvh's default (watertight), and obvh's fast (Moeller-Trumbore) test: the
    // last column shows what watertightness costs.
    LibraryRun runs[3];
    runs[0].lib = embree.get(), runs[0].name = "embree";
    runs[1].lib = obvh.get(), runs[1].name = "obvh";
    runs[2].lib = obvh.get(), runs[2].name = "obvh fast", runs[2].config = "intersector=fast";
    runs[2].defaultMode = false;
    for (LibraryRun& run : runs) {
      if (options.threads > 0)
        run.config += (run.config.empty() ? "" : ",") + std::string("threads=") + std::to_string(options.threads);
      run.device = run.lib->rtcNewDevice(run.config.c_str());
      if (!run.device) throw std::runtime_error(run.lib->label + ": rtcNewDevice failed");
      // One untimed build first: every library's first build also pays for fresh memory and
      // thread start-up, which depend on what ran before it in the process.
      { CommittedScene warmUp(*run.lib, run.device, scene, RTC_SCENE_FLAG_NONE, options.quality); }
      std::vector<double> buildTimes;
      for (int r = 0; r < options.runs; ++r) {
        run.scene.reset();
        buildTimes.push_back(millisecondsOf([&] {
          run.scene = std::make_unique<CommittedScene>(*run.lib, run.device, scene, RTC_SCENE_FLAG_NONE, options.quality);
        }));
        if (run.lib->rtcGetDeviceError(run.device) != RTC_ERROR_NONE)
          throw std::runtime_error(run.lib->label + ": committing the scene failed");
      }
      run.buildMs = median(buildTimes);
      // A separate verbose device: its statistics go to standard output, which is captured.
      const std::string verbose = run.config + (run.config.empty() ? "" : ",") + "verbose=2";
      run.sah = statisticsSahFromLog(captureStandardOutput([&] {
        RTCDevice device = run.lib->rtcNewDevice(verbose.c_str());
        { CommittedScene measured(*run.lib, device, scene, RTC_SCENE_FLAG_NONE, options.quality); }
        run.lib->rtcReleaseDevice(device);
      }));
      run.refitMs = refitMilliseconds(*run.lib, run.device, scene, options.runs);
      std::vector<double> lowTimes;
      for (int r = 0; r < options.runs; ++r)
        lowTimes.push_back(millisecondsOf([&] { CommittedScene low(*run.lib, run.device, scene, RTC_SCENE_FLAG_NONE, RTC_BUILD_QUALITY_LOW); }));
      run.lowBuildMs = median(lowTimes);
      run.memory = measureSceneMemory(*run.lib, run.config, scene, options.quality);
    }

    RTCBounds bounds;
    runs[0].lib->rtcGetSceneBounds(runs[0].scene->scene(), &bounds);
    const SceneBox box{{bounds.lower_x, bounds.lower_y, bounds.lower_z}, {bounds.upper_x, bounds.upper_y, bounds.upper_z}};
    const std::vector<RTCRay> perspective = perspectiveRays(box, options.width, options.height);
    const std::vector<RTCRay> orthographic = orthographicRays(box, options.width, options.height);
    const std::vector<RTCRay> random = randomRays(box, options.randomRays, 12345u);
    float source[3];
    for (int k = 0; k < 3; ++k) source[k] = options.hasSource ? options.source[k] : 0.5f * (box.lower[k] + box.upper[k]);
    const std::vector<RTCRay> fromSource = pointSourceRays(source, options.randomRays, 4242u);
    std::vector<Workload> workloads = {
        {"primary perspective", TracedQuery::Intersect1, &perspective, kCoherent},
        {"primary perspective, no coherence hint", TracedQuery::Intersect1, &perspective},
        {"primary perspective, packets of 8", TracedQuery::Intersect8, &perspective, kCoherent},
        {"primary perspective, packets of 8, no coherence hint", TracedQuery::Intersect8, &perspective},
        {"primary perspective, packets of 8 from one slot", TracedQuery::Intersect8OneSlot, &perspective, kCoherent},
        {"primary perspective, streams of 64 (rtcIntersect1M)", TracedQuery::Intersect1M, &perspective, kCoherent},
        {"primary orthographic", TracedQuery::Intersect1, &orthographic, kCoherent},
        {"primary orthographic, packets of 8", TracedQuery::Intersect8, &orthographic, kCoherent},
        {"random (incoherent)", TracedQuery::Intersect1, &random},
        {"from a point source", TracedQuery::Intersect1, &fromSource}};
    for (const Workload& w : workloads) traceInTurns(runs, w, options.runs);
    // Secondary rays start from Embree's primary hits so both libraries answer the very same rays.
    const std::vector<RTCRayHit>& embreePrimary = runs[0].results[0].hits;
    const std::vector<RTCRay> shadow = shadowRaysTowardsSceneLight(perspective, embreePrimary, box);
    const std::vector<RTCRay> diffuse = diffuseBounceRays(embreePrimary, 777u);
    const size_t firstSecondary = workloads.size();
    workloads.push_back({"diffuse bounce", TracedQuery::Intersect1, &diffuse});
    workloads.push_back({"shadow", TracedQuery::Occluded1, &shadow, kCoherent});
    workloads.push_back({"shadow, no coherence hint", TracedQuery::Occluded1, &shadow});
    workloads.push_back({"shadow, packets of 8", TracedQuery::Occluded8, &shadow, kCoherent});
    workloads.push_back({"shadow, packets of 8, no coherence hint", TracedQuery::Occluded8, &shadow});
    workloads.push_back({"shadow, streams of 64 (rtcOccluded1M)", TracedQuery::Occluded1M, &shadow, kCoherent});
    for (size_t k = firstSecondary; k < workloads.size(); ++k) traceInTurns(runs, workloads[k], options.runs);
    const size_t shadowRow = firstSecondary + 1;

    std::printf("obvh_bench: %s, %zu primitives, %dx%d pixels, %zu random rays, %zu diffuse bounces, median of %d runs, "
                "%d hardware threads\n",
                scene.name.c_str(), scene.primitiveCount(), options.width, options.height, random.size(), diffuse.size(),
                options.runs, int(std::thread::hardware_concurrency()));
    std::printf("  trace rows: the libraries take turns pass by pass; camera and shadow rows pass "
                "RTC_INTERSECT_CONTEXT_FLAG_COHERENT unless marked \"no coherence hint\"\n");
    if (options.threads > 0)
      // The devices' TBB limit holds for the whole process: with threads=1 every trace row ran at
      // half its two-thread rate.
      std::printf("  devices built with threads=%d, which also bounds the threads that trace the rays\n",
                  options.threads);
    std::printf("  point source at %g,%g,%g\n", double(source[0]), double(source[1]), double(source[2]));
    std::printf("  %-56s %10s %10s %10s %10s %10s\n", "", "embree", "obvh", "speed", "obvh fast", "speed");
    const char* qualityName = options.quality == RTC_BUILD_QUALITY_HIGH  ? "build ms (RTC_BUILD_QUALITY_HIGH)"
                              : options.quality == RTC_BUILD_QUALITY_LOW ? "build ms (RTC_BUILD_QUALITY_LOW)"
                                                                         : "build ms";
    printRow(qualityName, runs[0].buildMs, runs[1].buildMs, runs[2].buildMs, true);
    const auto mprims = [&](double ms) { return double(scene.primitiveCount()) / ms * 1e-3; };
    printRow("build Mprims/s", mprims(runs[0].buildMs), mprims(runs[1].buildMs), mprims(runs[2].buildMs), false);
    printRow("SAH cost (verbose=2 statistics)", runs[0].sah, runs[1].sah, runs[2].sah, true);
    printRow("build ms, RTC_BUILD_QUALITY_LOW", runs[0].lowBuildMs, runs[1].lowBuildMs, runs[2].lowBuildMs, true);
    printRow("refit ms (RTC_BUILD_QUALITY_REFIT)", runs[0].refitMs, runs[1].refitMs, runs[2].refitMs, true);
    // Geometry buffers included (the same bytes in both libraries); "speed" here is Embree / obvh. No
    // peak row: obvh reports its finished structure, not its build's temporary memory.
    printRow("memory MB held after commit (memory monitor)", runs[0].memory.heldMegabytes,
             runs[1].memory.heldMegabytes, runs[2].memory.heldMegabytes, true);
    for (size_t k = 0; k < workloads.size(); ++k)
      printRow((std::string(workloads[k].name) + " Mrays/s").c_str(), runs[0].results[k].mrays,
               runs[1].results[k].mrays, runs[2].results[k].mrays, false);

    bool clean = true;
    OcclusionJudge occlusionJudge(scene);
    for (int r = 1; r < 3; ++r) {
      std::printf("answers (embree vs %s):\n", runs[r].name);
      bool modeClean = true;
      for (size_t k = 0; k < workloads.size(); ++k) {
        const Workload& w = workloads[k];
        const MismatchCount c =
            isOcclusion(w.query)
                ? occlusionJudge.compare(*w.rays, runs[0].results[k].rays, runs[r].results[k].rays)
                : compareIntersections(scene, *w.rays, runs[0].results[k].hits, runs[r].results[k].hits);
        printCount(w.name, c);
        modeClean &= c.mismatched == 0;
      }
      // The fast intersector is not watertight by design (see the accuracy report): only obvh's
      // default mode must agree with Embree wherever the answer is not ambiguous.
      if (runs[r].defaultMode) clean &= modeClean;
    }

    std::filesystem::create_directories(options.outDir);
    const std::string stem = options.outDir + "/" + scene.name.substr(0, scene.name.find_last_of('.'));
    writeImage(stem + "_embree.png", options.width, options.height, shade(runs[0].results[0].hits, runs[0].results[shadowRow].rays));
    writeImage(stem + "_obvh.png", options.width, options.height, shade(runs[1].results[0].hits, runs[1].results[shadowRow].rays));
    std::printf("images: %s_embree.png %s_obvh.png\n", stem.c_str(), stem.c_str());

    for (LibraryRun& run : runs) {
      run.scene.reset();
      run.lib->rtcReleaseDevice(run.device);
    }
    if (!clean) std::printf("obvh_bench: unexplained mismatches found\n");
    return clean ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_bench: %s\n", e.what());
    return 2;
  }
}
