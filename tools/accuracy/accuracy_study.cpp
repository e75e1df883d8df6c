#include "accuracy_study.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>

#include "procedural_meshes.h"

namespace obvh::tools {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

RTCRay makeRay(const float org[3], const float dir[3]) {
  RTCRay ray{};
  ray.org_x = org[0], ray.org_y = org[1], ray.org_z = org[2];
  ray.dir_x = dir[0], ray.dir_y = dir[1], ray.dir_z = dir[2];
  ray.tnear = 0.f;
  ray.tfar = kInfinity;
  ray.mask = 0xFFFFFFFFu;
  return ray;
}

// Rays from points inside a closed convex mesh to every vertex and to points on every edge.
std::vector<RTCRay> raysAtEdgesAndVertices(const MeshData& mesh, const float inside[3], float jitter,
                                           size_t raysPerCase, std::mt19937& rng) {
  std::uniform_real_distribution<float> offset(-jitter, jitter);
  const size_t edges = 3 * mesh.primitiveCount();
  const size_t perEdge = std::max<size_t>(1, (raysPerCase + edges - 1) / edges);
  std::vector<RTCRay> rays;
  rays.reserve(edges * perEdge);
  for (size_t prim = 0; prim < mesh.primitiveCount(); ++prim)
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = mesh.indices[3 * prim + c], b = mesh.indices[3 * prim + (c + 1) % 3];
      for (size_t r = 0; r < perEdge; ++r) {
        const float w = float(r) / float(perEdge);  // r == 0 aims at the vertex itself
        float org[3], dir[3];
        for (int axis = 0; axis < 3; ++axis) {
          org[axis] = inside[axis] + offset(rng);
          dir[axis] = (1 - w) * mesh.vertices[3 * a + axis] + w * mesh.vertices[3 * b + axis] - org[axis];
        }
        rays.push_back(makeRay(org, dir));
      }
    }
  return rays;
}

struct Placement {
  std::string name;
  float scale;
  float offset;
};

// Far placements keep the mesh at 1e-4 of its distance from the origin, so that its edges still
// span a hundred or more float ulps there.
const Placement kPlacements[] = {{"origin", 1.f, 0.f},      {"at 1e4", 1.f, 1e4f},       {"at 1e5", 10.f, 1e5f},
                                 {"at 1e6", 100.f, 1e6f},   {"at 1e7", 1000.f, 1e7f},    {"scaled 1e-4", 1e-4f, 0.f},
                                 {"scaled 1e4", 1e4f, 0.f}};

double ulpOf(double value) {
  const float f = float(std::fabs(value));
  return double(std::nextafter(f, kInfinity)) - double(f);
}

// Context filter that records every primitive the ray reports and rejects the hit, so that
// traversal continues to the end of the ray.
struct CollectingContext {
  RTCIntersectContext context;
  unsigned prims[16];
  int count;
};

void collectEveryHit(const RTCFilterFunctionNArguments* args) {
  auto* collecting = reinterpret_cast<CollectingContext*>(args->context);
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, lane);
    const bool seen = std::find(collecting->prims, collecting->prims + collecting->count, prim) !=
                      collecting->prims + collecting->count;
    if (!seen && collecting->count < 16) collecting->prims[collecting->count++] = prim;
    args->valid[lane] = 0;
  }
}

struct Tally {
  size_t missed = 0, doubleReports = 0, falseHits = 0;
  double maxTErrorUlps = 0;
  std::string firstMiss, firstFalseHit;

  void add(const Tally& o) {
    missed += o.missed, doubleReports += o.doubleReports, falseHits += o.falseHits;
    maxTErrorUlps = std::max(maxTErrorUlps, o.maxTErrorUlps);
    if (firstMiss.empty()) firstMiss = o.firstMiss;
    if (firstFalseHit.empty()) firstFalseHit = o.firstFalseHit;
  }
};

// The primitives a ray may hit (exactly, or within rounding of an edge), for replaying a miss.
std::string primitivesMet(const SceneData& scene, const RTCRay& ray) {
  std::string out;
  for (unsigned geomID = 0; geomID < scene.meshes.size(); ++geomID)
    for (unsigned primID = 0; primID < scene.meshes[geomID].primitiveCount(); ++primID)
      if (hitIsPlausible(scene, ray, geomID, primID)) out += (out.empty() ? "" : "; ") + describePrimitive(scene, geomID, primID);
  return out.empty() ? "no primitive" : out;
}

void judgeRay(const HardCase& c, size_t i, const RTCRayHit& closest, bool occluded, int reportedPrimitives, Tally& tally) {
  const RTCRay& ray = c.rays[i];
  const bool hit = closest.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  const bool mustHit = c.kind == CaseKind::ClosedConvex || c.truth[i] == OcclusionTruth::Occluded;
  const bool mustMiss = c.kind == CaseKind::Grazing && c.truth[i] == OcclusionTruth::Free;
  if (mustHit && (!hit || !occluded)) {
    if (tally.missed++ == 0)
      tally.firstMiss = describeRay(ray) + (hit ? " (occluded said free)" : " (no hit)") + "; it meets " +
                        primitivesMet(c.scene, ray);
  }
  bool falseHit = mustMiss && (hit || occluded);
  if (hit && !hitIsPlausible(c.scene, ray, closest.hit.geomID, closest.hit.primID)) falseHit = true;
  if (falseHit && tally.falseHits++ == 0)
    tally.firstFalseHit = describeRay(ray) + (hit ? "; reported " + describePrimitive(c.scene, closest.hit.geomID,
                                                                                    closest.hit.primID)
                                                  : std::string("; occluded said occluded"));
  if (c.kind == CaseKind::ClosedConvex && reportedPrimitives > 1) ++tally.doubleReports;
  if (hit) {
    for (const ExactPart& part : intersectExact(c.scene, ray, closest.hit.geomID, closest.hit.primID)) {
      if (!part.planeHit) continue;
      tally.maxTErrorUlps = std::max(tally.maxTErrorUlps, std::fabs(closest.ray.tfar - part.t) / ulpOf(part.t));
    }
  }
}

}  // namespace

std::vector<AccuracyMode> standardModes(const RtcLibrary& embree, const RtcLibrary& obvh) {
  return {{"obvh watertight", &obvh, "", RTC_SCENE_FLAG_NONE},
          {"obvh robust flag", &obvh, "", RTC_SCENE_FLAG_ROBUST},
          {"obvh fast", &obvh, "intersector=fast", RTC_SCENE_FLAG_NONE},
          {"embree default", &embree, "", RTC_SCENE_FLAG_NONE},
          {"embree robust", &embree, "", RTC_SCENE_FLAG_ROBUST}};
}

std::vector<HardCase> closedMeshCases(size_t raysPerCase, uint32_t seed) {
  const float zero[3] = {0.f, 0.f, 0.f}, lower[3] = {-1.f, -1.f, -1.f}, upper[3] = {1.f, 1.f, 1.f};
  struct Shape {
    std::string name;
    MeshData mesh;
    float inside[3];
  };
  const Shape shapes[] = {{"icosphere", icosphere(3, 1.f, zero), {0.1f, -0.2f, 0.15f}},
                          {"cube grid", cubeGrid(8, lower, upper), {0.2f, 0.1f, -0.3f}},
                          {"closed fan", closedFan(256, 1.f, 1.f, zero), {0.05f, -0.1f, 0.1f}}};
  std::mt19937 rng(seed);
  std::vector<HardCase> cases;
  for (const Shape& shape : shapes)
    for (const Placement& placement : kPlacements) {
      HardCase c;
      c.name = shape.name + " " + placement.name;
      c.kind = CaseKind::ClosedConvex;
      MeshData mesh = shape.mesh;
      const float offset[3] = {placement.offset, -placement.offset, 0.5f * placement.offset};
      transformMesh(mesh, placement.scale, offset);
      float inside[3];
      for (int k = 0; k < 3; ++k) inside[k] = shape.inside[k] * placement.scale + offset[k];
      c.rays = raysAtEdgesAndVertices(mesh, inside, 0.1f * placement.scale, raysPerCase, rng);
      c.scene.name = c.name;
      c.scene.meshes.push_back(std::move(mesh));
      cases.push_back(std::move(c));
    }
  return cases;
}

HardCase grazingSkinnyCase(size_t triangles, size_t rays, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto randomUnit = [&] {
    double v[3], length;
    do {
      for (double& x : v) x = 2.0 * unit(rng) - 1.0;
      length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (length < 0.1 || length > 1.0);
    return std::array<double, 3>{v[0] / length, v[1] / length, v[2] / length};
  };
  auto cross = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    std::array<double, 3> c{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    const double l = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (double& x : c) x /= l;
    return c;
  };

  HardCase c;
  c.name = "skinny triangles, grazing rays";
  c.kind = CaseKind::Grazing;
  c.scene.name = c.name;
  MeshData mesh;
  struct Frame {
    std::array<double, 3> start, along, across, normal;
  };
  std::vector<Frame> frames;
  for (size_t i = 0; i < triangles; ++i) {
    Frame f;
    for (double& x : f.start) x = unit(rng);
    f.along = randomUnit();
    f.normal = cross(f.along, randomUnit());
    f.across = cross(f.normal, f.along);
    const double width = std::pow(10.0, -6.0 + 3.0 * unit(rng));
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(float(f.start[k]));
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(float(f.start[k] + f.along[k]));
    for (int k = 0; k < 3; ++k) mesh.vertices.push_back(float(f.start[k] + 0.5 * f.along[k] + width * f.across[k]));
    mesh.indices.insert(mesh.indices.end(), {uint32_t(3 * i), uint32_t(3 * i + 1), uint32_t(3 * i + 2)});
    frames.push_back(f);
  }
  c.scene.meshes.push_back(std::move(mesh));

  for (size_t r = 0; r < rays; ++r) {
    const Frame& f = frames[size_t(unit(rng) * double(triangles)) % triangles];
    const double along = 0.1 + 0.8 * unit(rng);
    const double side = unit(rng) < 0.5 ? -1.0 : 1.0;
    const double lateral = side * std::pow(10.0, -9.0 + 5.0 * unit(rng));
    const double angle = std::pow(10.0, -4.0 + 3.0 * unit(rng)) * (unit(rng) < 0.5 ? -1.0 : 1.0);
    const double heading = 2.0 * 3.14159265358979 * unit(rng);
    float org[3], dir[3];
    for (int k = 0; k < 3; ++k) {
      const double target = f.start[k] + along * f.along[k] + lateral * f.across[k];
      const double inPlane = std::cos(heading) * f.along[k] + std::sin(heading) * f.across[k];
      const double d = std::cos(angle) * inPlane + std::sin(angle) * f.normal[k];
      dir[k] = float(d);
      org[k] = float(target - 2.0 * d);
    }
    c.rays.push_back(makeRay(org, dir));
  }
  c.truth.resize(c.rays.size());
  tbb::parallel_for(size_t(0), c.rays.size(), [&](size_t i) { c.truth[i] = exactOcclusion(c.scene, c.rays[i]); });
  return c;
}

CaseResult runCase(const AccuracyMode& mode, const HardCase& c) {
  const RtcLibrary& lib = *mode.lib;
  RTCDevice device = lib.rtcNewDevice(mode.config.empty() ? nullptr : mode.config.c_str());
  if (!device) throw std::runtime_error(mode.name + ": rtcNewDevice(\"" + mode.config + "\") failed");
  Tally total;
  {
    const CommittedScene scene(lib, device, c.scene, mode.flags);
    const CommittedScene collecting(lib, device, c.scene, RTCSceneFlags(mode.flags | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    if (lib.rtcGetDeviceError(device) != RTC_ERROR_NONE) throw std::runtime_error(mode.name + ": commit failed");
    std::mutex merge;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, c.rays.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
      Tally tally;
      for (size_t i = range.begin(); i < range.end(); ++i) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit closest{};
        closest.ray = c.rays[i];
        closest.hit.geomID = closest.hit.primID = closest.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        lib.rtcIntersect1(scene.scene(), &context, &closest);
        RTCRay shadow = c.rays[i];
        lib.rtcOccluded1(scene.scene(), &context, &shadow);
        const bool occluded = shadow.tfar == -kInfinity;
        int reported = 0;
        if (c.kind == CaseKind::ClosedConvex) {
          CollectingContext every{};
          rtcInitIntersectContext(&every.context);
          every.context.filter = collectEveryHit;
          RTCRayHit all{};
          all.ray = c.rays[i];
          all.hit.geomID = all.hit.primID = all.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          lib.rtcIntersect1(collecting.scene(), &every.context, &all);
          reported = every.count;
        }
        judgeRay(c, i, closest, occluded, reported, tally);
      }
      const std::lock_guard<std::mutex> lock(merge);
      total.add(tally);
    });
  }
  lib.rtcReleaseDevice(device);
  CaseResult result;
  result.caseName = c.name;
  result.kind = c.kind;
  result.rays = c.rays.size();
  result.missed = total.missed;
  result.doubleReports = total.doubleReports;
  result.falseHits = total.falseHits;
  result.maxTErrorUlps = total.maxTErrorUlps;
  result.firstMiss = total.firstMiss;
  result.firstFalseHit = total.firstFalseHit;
  return result;
}

}  // namespace obvh::tools
