#include "crossval_harness.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <random>

#include "ray_generation.h"

namespace obvh::test {

const LoadedLibraries& libraries() {
  static const LoadedLibraries loaded = [] {
    static std::unique_ptr<RtcLibrary> embree, obvh;
    std::string error;
    embree = RtcLibrary::open(tools::referenceEmbreePath(), "embree", error);
    if (embree) obvh = RtcLibrary::open(tools::obvhDropInPath(), "obvh", error);
    if (!embree || !obvh) {
      std::fprintf(stderr, "crossval: %s\n", error.c_str());
      std::abort();
    }
    LoadedLibraries l;
    l.embree = embree.get();
    l.obvh = obvh.get();
    l.embreeDevice = embree->rtcNewDevice("isa=avx2");
    l.obvhDevice = obvh->rtcNewDevice(nullptr);
    if (!l.embreeDevice || !l.obvhDevice) {
      std::fprintf(stderr, "crossval: rtcNewDevice failed\n");
      std::abort();
    }
    return l;
  }();
  return loaded;
}

void CrossvalCounts::add(const tools::Comparison& c, const RTCRay& ray) {
  ++rays;
  if (c.verdict == tools::Verdict::Equal) return;
  ++differing;
  if (c.verdict == tools::Verdict::Ambiguous) {
    ++ambiguous;
    return;
  }
  ++mismatched;
  if (examples.size() < 5) examples.push_back(tools::describeRay(ray) + ": " + c.reason);
}

std::string CrossvalCounts::summary() const {
  std::string s = std::to_string(rays) + " rays, " + std::to_string(differing) + " differ, " +
                  std::to_string(ambiguous) + " proven ambiguous, " + std::to_string(mismatched) + " mismatches";
  for (const std::string& e : examples) s += "\n  mismatch: " + e;
  return s;
}

namespace {

std::vector<RTCRayHit> trace(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays,
                             RTCIntersectContextFlags contextFlags) {
  std::vector<RTCRayHit> out(rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = contextFlags;
  for (size_t i = 0; i < rays.size(); ++i) {
    out[i].ray = rays[i];
    out[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
    lib.rtcIntersect1(scene, &context, &out[i]);
  }
  return out;
}

}  // namespace

CrossvalCounts compareCommitted(const SceneData& scene, const tools::CommittedScene& reference,
                                const tools::CommittedScene& candidate, const std::vector<RTCRay>& rays,
                                RTCIntersectContextFlags contextFlags) {
  const LoadedLibraries& libs = libraries();
  const std::vector<RTCRayHit> a = trace(*libs.embree, reference.scene(), rays, contextFlags);
  const std::vector<RTCRayHit> b = trace(*libs.obvh, candidate.scene(), rays, contextFlags);
  CrossvalCounts counts;
  for (size_t i = 0; i < rays.size(); ++i)
    counts.add(tools::compareHits(scene, rays[i], tools::toHitRecord(a[i]), tools::toHitRecord(b[i])), rays[i]);
  return counts;
}

ObvhDevice::ObvhDevice(const char* config) : device_(libraries().obvh->rtcNewDevice(config)) {}

ObvhDevice::~ObvhDevice() {
  if (device_) libraries().obvh->rtcReleaseDevice(device_);
}

void expectNoMismatch(const char* what, const CrossvalCounts& counts) {
  std::printf("[crossval] %-34s %s\n", what, counts.summary().c_str());
  ::testing::Test::RecordProperty(std::string(what) + "_rays", std::to_string(counts.rays));
  ::testing::Test::RecordProperty(std::string(what) + "_ambiguous", std::to_string(counts.ambiguous));
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
}

SceneData single(const char* name, tools::MeshData mesh) {
  SceneData scene;
  scene.name = name;
  scene.meshes.push_back(std::move(mesh));
  return scene;
}

CrossvalCounts crossvalIntersect1(const SceneData& scene, const std::vector<RTCRay>& rays, RTCSceneFlags flags) {
  const LoadedLibraries& libs = libraries();
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene, flags);
  tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene, flags);
  return compareCommitted(scene, reference, candidate, rays);
}

void judgeOcclusion(const SceneData& scene, const RTCRay& ray, bool embreeOccluded, bool obvhOccluded,
                    CrossvalCounts& counts) {
  counts.add(tools::compareOcclusion(scene, ray, embreeOccluded, obvhOccluded), ray);
}

CrossvalCounts compareCommittedOcclusion(const SceneData& scene, const tools::CommittedScene& reference,
                                         const tools::CommittedScene& candidate, const std::vector<RTCRay>& rays,
                                         RTCIntersectContextFlags contextFlags) {
  const LoadedLibraries& libs = libraries();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = contextFlags;
  CrossvalCounts counts;
  for (const RTCRay& ray : rays) {
    RTCRay a = ray, b = ray;
    libs.embree->rtcOccluded1(reference.scene(), &context, &a);
    libs.obvh->rtcOccluded1(candidate.scene(), &context, &b);
    const float hit = -std::numeric_limits<float>::infinity();
    judgeOcclusion(scene, ray, a.tfar == hit, b.tfar == hit, counts);
  }
  return counts;
}

CrossvalCounts crossvalOccluded1(const SceneData& scene, const std::vector<RTCRay>& rays, RTCSceneFlags flags) {
  const LoadedLibraries& libs = libraries();
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene, flags);
  tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene, flags);
  return compareCommittedOcclusion(scene, reference, candidate, rays);
}

std::vector<RTCRay> raysThroughEdgesAndVertices(const tools::MeshData& mesh, size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  const int corners = mesh.quads ? 4 : 3;
  std::vector<RTCRay> rays;
  rays.reserve(count);
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], mesh.vertices[i]);
    hi[i % 3] = std::max(hi[i % 3], mesh.vertices[i]);
  }
  float extent = 0.f, center[3];
  for (int k = 0; k < 3; ++k) {
    extent = std::max(extent, hi[k] - lo[k]);
    center[k] = 0.5f * (lo[k] + hi[k]);
  }
  std::uniform_int_distribution<size_t> pickPrim(0, mesh.primitiveCount() - 1);
  std::uniform_int_distribution<int> pickCorner(0, corners - 1);
  for (size_t i = 0; i < count; ++i) {
    const size_t prim = pickPrim(rng);
    const int c0 = pickCorner(rng), c1 = (c0 + 1) % corners;
    const uint32_t a = mesh.indices[prim * corners + c0], b = mesh.indices[prim * corners + c1];
    const bool throughVertex = (i % 3) == 0;
    float target[3], org[3];
    for (int k = 0; k < 3; ++k)
      target[k] = throughVertex ? mesh.vertices[3 * a + k] : 0.5f * (mesh.vertices[3 * a + k] + mesh.vertices[3 * b + k]);
    for (int k = 0; k < 3; ++k) org[k] = center[k] + 2.f * extent * unit(rng);
    RTCRay r{};
    r.org_x = org[0], r.org_y = org[1], r.org_z = org[2];
    r.dir_x = target[0] - org[0], r.dir_y = target[1] - org[1], r.dir_z = target[2] - org[2];
    r.tnear = 0.f;
    r.tfar = std::numeric_limits<float>::infinity();
    r.mask = 0xFFFFFFFFu;
    rays.push_back(r);
  }
  return rays;
}

std::vector<RTCRay> mixedRays(const SceneData& scene, size_t randomCount, int gridSide, uint32_t seed) {
  tools::SceneBox box{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
  for (const tools::MeshData& mesh : scene.meshes)
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
      box.lower[i % 3] = std::min(box.lower[i % 3], mesh.vertices[i]);
      box.upper[i % 3] = std::max(box.upper[i % 3], mesh.vertices[i]);
    }
  std::vector<RTCRay> rays = tools::randomRays(box, randomCount, seed);
  const std::vector<RTCRay> grid = tools::orthographicRays(box, gridSide, gridSide);
  rays.insert(rays.end(), grid.begin(), grid.end());
  return rays;
}

void assignRandomTimes(std::vector<RTCRay>& rays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (RTCRay& r : rays) r.time = unit(rng);
}

void assignMasks(std::vector<RTCRay>& rays, uint32_t seed) {
  const unsigned patterns[] = {0xFFFFFFFFu, 0x1u, 0x2u, 0x4u, 0x6u, 0x0u};
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, 5);
  for (RTCRay& r : rays) r.mask = patterns[pick(rng)];
}

}  // namespace obvh::test
