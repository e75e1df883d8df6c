// Cross-validation harness: Debian's Embree (reference) and obvh's drop-in (candidate) loaded side by
// side; the same scene is committed to both, the same rays traced, every answer compared.
#pragma once

#include <string>
#include <vector>

#include "hit_compare.h"
#include "rtc_library.h"
#include "scene_data.h"

namespace obvh::test {

using tools::HitRecord;
using tools::RtcLibrary;
using tools::SceneData;

struct LoadedLibraries {
  RtcLibrary* embree = nullptr;
  RtcLibrary* obvh = nullptr;
  RTCDevice embreeDevice = nullptr;  // isa=avx2: see DESIGN.md (Embree's AVX-512 path hangs in places)
  RTCDevice obvhDevice = nullptr;
};

// An extra obvh device with its own config string (accel=..., intersector=...), released at scope end.
class ObvhDevice {
 public:
  explicit ObvhDevice(const char* config);
  ~ObvhDevice();
  ObvhDevice(const ObvhDevice&) = delete;
  ObvhDevice& operator=(const ObvhDevice&) = delete;
  RTCDevice get() const { return device_; }

 private:
  RTCDevice device_;
};

// Loaded once per process; aborts the test binary with a clear message when a library is missing.
const LoadedLibraries& libraries();

struct CrossvalCounts {
  size_t rays = 0, differing = 0, ambiguous = 0, mismatched = 0;
  std::vector<std::string> examples;  // the first few mismatches, replayable (hex floats)

  void add(const tools::Comparison& c, const RTCRay& ray);
  std::string summary() const;
};

// Commits scene to both libraries, traces rays with rtcIntersect1 through each and compares.
CrossvalCounts crossvalIntersect1(const SceneData& scene, const std::vector<RTCRay>& rays,
                                  RTCSceneFlags flags = RTC_SCENE_FLAG_NONE);
// Traces rays with rtcIntersect1 through two already committed scenes and compares every answer;
// both libraries get an intersect context with contextFlags.
CrossvalCounts compareCommitted(const SceneData& scene, const tools::CommittedScene& reference,
                                const tools::CommittedScene& candidate, const std::vector<RTCRay>& rays,
                                RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
// rtcOccluded1 through two committed scenes; a differing answer is judged in double precision.
CrossvalCounts compareCommittedOcclusion(const SceneData& scene, const tools::CommittedScene& reference,
                                         const tools::CommittedScene& candidate, const std::vector<RTCRay>& rays,
                                         RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
// The same for rtcOccluded1; a differing answer is judged by a brute-force double-precision test.
CrossvalCounts crossvalOccluded1(const SceneData& scene, const std::vector<RTCRay>& rays,
                                 RTCSceneFlags flags = RTC_SCENE_FLAG_NONE);

// Judges occlusion answers of both libraries for one ray.
void judgeOcclusion(const SceneData& scene, const RTCRay& ray, bool embreeOccluded, bool obvhOccluded,
                    CrossvalCounts& counts);

// Prints the counts, records them as test properties and expects no mismatch.
void expectNoMismatch(const char* what, const CrossvalCounts& counts);

// A scene of one mesh.
SceneData single(const char* name, tools::MeshData mesh);

// Rays through the vertices and edge midpoints of mesh (shared edges of a closed mesh), seeded.
std::vector<RTCRay> raysThroughEdgesAndVertices(const tools::MeshData& mesh, size_t count, uint32_t seed);

// Random incoherent rays plus an orthographic grid of coherent rays over the scene's bounds.
std::vector<RTCRay> mixedRays(const SceneData& scene, size_t randomCount, int gridSide, uint32_t seed);

// Sets every ray's mask from a small set of patterns (all, single bits, none), seeded.
void assignMasks(std::vector<RTCRay>& rays, uint32_t seed);

// Sets every ray's time uniformly in the shutter [0, 1], seeded.
void assignRandomTimes(std::vector<RTCRay>& rays, uint32_t seed);

}  // namespace obvh::test
