// Instances, user geometry, filter callbacks and interpolation through obvh and Debian's Embree.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "crossval_harness.h"
#include "ray_generation.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

constexpr size_t kRays = 100000;

RTCGeometry addMesh(const RtcLibrary& lib, RTCDevice device, RTCScene scene, const MeshData& mesh) {
  RTCGeometry g = lib.rtcNewGeometry(
      device, mesh.grid ? RTC_GEOMETRY_TYPE_GRID : mesh.quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(
      lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, mesh.vertexCount()));
  std::memcpy(v, mesh.vertices.data(), mesh.vertices.size() * sizeof(float));
  if (mesh.grid) {
    void* grids = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid),
                                              mesh.primitiveCount());
    std::memcpy(grids, mesh.grids.data(), mesh.grids.size() * sizeof(RTCGrid));
  } else {
    auto* i = static_cast<uint32_t*>(lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                                 mesh.quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                                                 mesh.quads ? 16 : 12, mesh.primitiveCount()));
    std::memcpy(i, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t));
  }
  lib.rtcCommitGeometry(g);
  lib.rtcAttachGeometry(scene, g);
  return g;
}

std::vector<RTCRay> raysAround(float lo, float hi, size_t count, uint32_t seed) {
  const tools::SceneBox box{{lo, lo, lo}, {hi, hi, hi}};
  return tools::randomRays(box, count, seed);
}

std::vector<RTCRayHit> traceAll(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays,
                                RTCIntersectContext* context) {
  std::vector<RTCRayHit> out(rays.size());
  for (size_t k = 0; k < rays.size(); ++k) {
    out[k].ray = rays[k];
    out[k].hit.geomID = out[k].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    lib.rtcIntersect1(scene, context, &out[k]);
  }
  return out;
}

// --- Instances ----------------------------------------------------------------------------------

// A committed scene of the meshes, geomIDs in their order.
RTCScene committedSceneOf(const RtcLibrary& lib, RTCDevice device, std::initializer_list<const MeshData*> meshes) {
  RTCScene scene = lib.rtcNewScene(device);
  for (const MeshData* mesh : meshes) lib.rtcReleaseGeometry(addMesh(lib, device, scene, *mesh));
  lib.rtcCommitScene(scene);
  return scene;
}

// rtcOccluded1 of the first `count` rays through Embree's scenes[0] and obvh's scenes[1], each
// answer judged against the flattened world flatFor(k) of ray k.
template <typename FlatFor>
CrossvalCounts occlusionThroughBoth(RTCScene scenes[2], const std::vector<RTCRay>& rays, size_t count,
                                    RTCIntersectContext* context, FlatFor&& flatFor) {
  const LoadedLibraries& libs = libraries();
  CrossvalCounts occlusion;
  for (size_t k = 0; k < count; ++k) {
    RTCRay ra = rays[k], rb = rays[k];
    libs.embree->rtcOccluded1(scenes[0], context, &ra);
    libs.obvh->rtcOccluded1(scenes[1], context, &rb);
    const float blocked = -std::numeric_limits<float>::infinity();
    judgeOcclusion(flatFor(k), rays[k], ra.tfar == blocked, rb.tfar == blocked, occlusion);
  }
  return occlusion;
}

struct InstancePlacement {
  float m[12];  // 3x4 column major: columns vx, vy, vz, p
};

std::vector<InstancePlacement> randomPlacements(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  std::vector<InstancePlacement> out;
  for (int k = 0; k < count; ++k) {
    // Rotation about a random axis, non-uniform scale, translation.
    float ax = unit(rng), ay = unit(rng), az = unit(rng);
    const float len = std::sqrt(ax * ax + ay * ay + az * az) + 1e-6f;
    ax /= len, ay /= len, az /= len;
    const float angle = 3.14159f * unit(rng), c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    const float rot[9] = {t * ax * ax + c,      t * ax * ay + s * az, t * ax * az - s * ay,
                          t * ax * ay - s * az, t * ay * ay + c,      t * ay * az + s * ax,
                          t * ax * az + s * ay, t * ay * az - s * ax, t * az * az + c};
    const float scale[3] = {0.5f + 0.4f * unit(rng), 0.5f + 0.4f * unit(rng), 0.5f + 0.4f * unit(rng)};
    InstancePlacement p;
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) p.m[3 * col + row] = rot[3 * col + row] * scale[col];
    for (int row = 0; row < 3; ++row) p.m[9 + row] = 6.f * unit(rng);
    out.push_back(p);
  }
  return out;
}

// Sets the transform in one of Embree's three matrix formats, chosen by k.
void setTransform(const RtcLibrary& lib, RTCGeometry g, const InstancePlacement& p, int k) {
  const float* m = p.m;
  if (k % 3 == 0) {
    lib.rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
  } else if (k % 3 == 1) {
    const float row[12] = {m[0], m[3], m[6], m[9], m[1], m[4], m[7], m[10], m[2], m[5], m[8], m[11]};
    lib.rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, row);
  } else {
    const float col4[16] = {m[0], m[1], m[2], 0, m[3], m[4], m[5], 0, m[6], m[7], m[8], 0, m[9], m[10], m[11], 1};
    lib.rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, col4);
  }
}

// The same world geometry without instancing, for the double-precision judge.
void appendTransformed(SceneData& flat, const MeshData& mesh, const InstancePlacement& p) {
  MeshData world = mesh;
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    const float x = mesh.vertices[3 * v], y = mesh.vertices[3 * v + 1], z = mesh.vertices[3 * v + 2];
    for (int r = 0; r < 3; ++r) world.vertices[3 * v + r] = p.m[r] * x + p.m[3 + r] * y + p.m[6 + r] * z + p.m[9 + r];
  }
  flat.meshes.push_back(world);
}

TEST(CrossvalInstances, TransformedInstancesMatchEmbreeIncludingInstId) {
  const LoadedLibraries& libs = libraries();
  const float center[3] = {0.f, 0.f, 0.f}, lo[3] = {-1.5f, -0.2f, -1.5f}, hi[3] = {1.5f, 0.2f, 1.5f};
  const MeshData child0 = icosphere(3, 1.f, center), child1 = box(lo, hi, true);
  const MeshData ground = quadGrid(8, 0.f, 1);
  const std::vector<InstancePlacement> placements = randomPlacements(24, 7);

  RTCScene scenes[2];
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  for (int k = 0; k < 2; ++k) {
    RTCScene child = committedSceneOf(*lib[k], devices[k], {&child0, &child1});
    scenes[k] = lib[k]->rtcNewScene(devices[k]);
    lib[k]->rtcReleaseGeometry(addMesh(*lib[k], devices[k], scenes[k], ground));  // geomID 0: plain mesh
    for (size_t p = 0; p < placements.size(); ++p) {
      RTCGeometry inst = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_INSTANCE);
      lib[k]->rtcSetGeometryInstancedScene(inst, child);
      setTransform(*lib[k], inst, placements[p], int(p));
      lib[k]->rtcCommitGeometry(inst);
      lib[k]->rtcAttachGeometry(scenes[k], inst);  // geomID p + 1
      lib[k]->rtcReleaseGeometry(inst);
    }
    lib[k]->rtcCommitScene(scenes[k]);
    lib[k]->rtcReleaseScene(child);
    ASSERT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE) << lib[k]->label;
  }
  // Flattened world geometry: mesh 0 = ground, then 2 meshes per instance.
  SceneData flat;
  flat.meshes.push_back(ground);
  for (const InstancePlacement& p : placements) {
    appendTransformed(flat, child0, p);
    appendTransformed(flat, child1, p);
  }
  auto flatten = [](const RTCRayHit& rh) {
    HitRecord h = tools::toHitRecord(rh);
    if (h.hit() && rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) h.geomID = 1 + 2 * (rh.hit.instID[0] - 1) + h.geomID;
    return h;
  };
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const std::vector<RTCRay> rays = raysAround(-8.f, 8.f, kRays, 8);
  const std::vector<RTCRayHit> a = traceAll(*libs.embree, scenes[0], rays, &context);
  const std::vector<RTCRayHit> b = traceAll(*libs.obvh, scenes[1], rays, &context);
  CrossvalCounts counts;
  size_t instanceHits = 0, instIdDiffers = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    counts.add(tools::compareHits(flat, rays[k], flatten(a[k]), flatten(b[k])), rays[k]);
    if (a[k].hit.geomID != RTC_INVALID_GEOMETRY_ID && a[k].hit.instID[0] != RTC_INVALID_GEOMETRY_ID) ++instanceHits;
    if (a[k].hit.geomID == b[k].hit.geomID && a[k].hit.primID == b[k].hit.primID &&
        a[k].hit.instID[0] != b[k].hit.instID[0])
      ++instIdDiffers;
  }
  std::printf("[crossval] %-34s %s (%zu instance hits)\n", "instances", counts.summary().c_str(), instanceHits);
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
  EXPECT_GT(instanceHits, kRays / 10);
  EXPECT_EQ(instIdDiffers, 0u);

  // Occlusion through instances.
  const CrossvalCounts occlusion = occlusionThroughBoth(scenes, rays, 20000, &context, [&](size_t) -> const SceneData& { return flat; });
  std::printf("[crossval] %-34s %s\n", "instances occluded", occlusion.summary().c_str());
  EXPECT_EQ(occlusion.mismatched, 0u) << occlusion.summary();

  float back[2][12];
  libs.embree->rtcGetGeometryTransform(libs.embree->rtcGetGeometry(scenes[0], 2), 0.f, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, back[0]);
  libs.obvh->rtcGetGeometryTransform(libs.obvh->rtcGetGeometry(scenes[1], 2), 0.f, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, back[1]);
  for (int k = 0; k < 12; ++k) EXPECT_FLOAT_EQ(back[0][k], back[1][k]);
  libs.embree->rtcReleaseScene(scenes[0]);
  libs.obvh->rtcReleaseScene(scenes[1]);
}

TEST(CrossvalInstances, QuaternionDecompositionMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  RTCQuaternionDecomposition qd;
  rtcInitQuaternionDecomposition(&qd);
  rtcQuaternionDecompositionSetScale(&qd, 1.5f, 0.7f, 2.f);
  rtcQuaternionDecompositionSetSkew(&qd, 0.1f, -0.2f, 0.3f);
  rtcQuaternionDecompositionSetShift(&qd, 0.5f, -1.f, 0.25f);
  const float angle = 0.8f, axis[3] = {0.267f, 0.535f, 0.802f};
  rtcQuaternionDecompositionSetQuaternion(&qd, std::cos(angle / 2), axis[0] * std::sin(angle / 2),
                                          axis[1] * std::sin(angle / 2), axis[2] * std::sin(angle / 2));
  rtcQuaternionDecompositionSetTranslation(&qd, 3.f, -2.f, 1.f);
  float m[2][12];
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  for (int k = 0; k < 2; ++k) {
    RTCGeometry inst = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_INSTANCE);
    lib[k]->rtcSetGeometryTransformQuaternion(inst, 0, &qd);
    lib[k]->rtcGetGeometryTransform(inst, 0.f, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m[k]);
    EXPECT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
    lib[k]->rtcReleaseGeometry(inst);
  }
  for (int k = 0; k < 12; ++k) EXPECT_NEAR(m[0][k], m[1][k], 1e-5f) << "element " << k;
}

// Motion blur of instances: linear blends of three transforms, and quaternion decompositions whose
// rotation turns (interpolated along the sphere). Rays are traced at a few times; at each, the
// world is flattened with Embree's own transform at that time (rtcGetGeometryTransform), which
// obvh's must match, and both libraries' hits are judged against it.
TEST(CrossvalInstances, MovingInstancesMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  const float center[3] = {0.f, 0.f, 0.f}, lo[3] = {-1.5f, -0.2f, -1.5f}, hi[3] = {1.5f, 0.2f, 1.5f};
  const MeshData child0 = icosphere(3, 1.f, center), child1 = box(lo, hi, true);
  const std::vector<InstancePlacement> placements = randomPlacements(12, 9);  // 4 instances x 3 steps
  const int linearCount = 2, instanceCount = 4, steps = 3;
  const float times[5] = {0.f, 0.13f, 0.5f, 0.77f, 1.f};

  RTCScene scenes[2];
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  for (int k = 0; k < 2; ++k) {
    RTCScene child = committedSceneOf(*lib[k], devices[k], {&child0, &child1});
    scenes[k] = lib[k]->rtcNewScene(devices[k]);
    for (int i = 0; i < instanceCount; ++i) {
      RTCGeometry inst = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_INSTANCE);
      lib[k]->rtcSetGeometryInstancedScene(inst, child);
      lib[k]->rtcSetGeometryTimeStepCount(inst, steps);
      for (int step = 0; step < steps; ++step) {
        if (i < linearCount) {
          lib[k]->rtcSetGeometryTransform(inst, step, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, placements[i * steps + step].m);
          continue;
        }
        RTCQuaternionDecomposition qd;
        rtcInitQuaternionDecomposition(&qd);
        rtcQuaternionDecompositionSetScale(&qd, 0.8f + 0.1f * step, 0.6f, 1.1f);
        rtcQuaternionDecompositionSetSkew(&qd, 0.1f * i, 0.f, -0.05f * step);
        rtcQuaternionDecompositionSetShift(&qd, 0.3f, 0.f, -0.2f);
        const float angle = 1.2f * float(step) + 0.4f * float(i), axis[3] = {0.267f, 0.802f, 0.535f};
        rtcQuaternionDecompositionSetQuaternion(&qd, std::cos(angle / 2), axis[0] * std::sin(angle / 2),
                                                axis[1] * std::sin(angle / 2), axis[2] * std::sin(angle / 2));
        rtcQuaternionDecompositionSetTranslation(&qd, 3.f * float(i - 2), 0.5f * float(step), -1.f);
        lib[k]->rtcSetGeometryTransformQuaternion(inst, step, &qd);
      }
      lib[k]->rtcCommitGeometry(inst);
      lib[k]->rtcAttachGeometry(scenes[k], inst);  // geomID i
      lib[k]->rtcReleaseGeometry(inst);
    }
    lib[k]->rtcCommitScene(scenes[k]);
    lib[k]->rtcReleaseScene(child);
    ASSERT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE) << lib[k]->label;
  }
  // The world at each time, placed with Embree's transforms; obvh's must be the same.
  SceneData flat[5];
  for (int t = 0; t < 5; ++t)
    for (int i = 0; i < instanceCount; ++i) {
      InstancePlacement placed[2];
      for (int k = 0; k < 2; ++k)
        lib[k]->rtcGetGeometryTransform(lib[k]->rtcGetGeometry(scenes[k], unsigned(i)), times[t],
                                        RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, placed[k].m);
      for (int e = 0; e < 12; ++e)
        EXPECT_NEAR(placed[0].m[e], placed[1].m[e], 1e-4f * (1.f + std::fabs(placed[0].m[e])))
            << "instance " << i << " time " << times[t] << " element " << e;
      appendTransformed(flat[t], child0, placed[0]);
      appendTransformed(flat[t], child1, placed[0]);
    }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::vector<RTCRay> rays = raysAround(-8.f, 8.f, kRays, 10);
  for (size_t k = 0; k < rays.size(); ++k) rays[k].time = times[k % 5];
  const std::vector<RTCRayHit> a = traceAll(*libs.embree, scenes[0], rays, &context);
  const std::vector<RTCRayHit> b = traceAll(*libs.obvh, scenes[1], rays, &context);
  auto flatten = [](const RTCRayHit& rh) {
    HitRecord h = tools::toHitRecord(rh);
    if (h.hit()) h.geomID = 2 * rh.hit.instID[0] + h.geomID;
    return h;
  };
  CrossvalCounts counts;
  size_t hits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    counts.add(tools::compareHits(flat[k % 5], rays[k], flatten(a[k]), flatten(b[k])), rays[k]);
    hits += a[k].hit.geomID != RTC_INVALID_GEOMETRY_ID;
  }
  std::printf("[crossval] %-34s %s (%zu hits)\n", "moving instances", counts.summary().c_str(), hits);
  EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
  EXPECT_GT(hits, kRays / 20);
  const CrossvalCounts occlusion =
      occlusionThroughBoth(scenes, rays, 20000, &context, [&](size_t k) -> const SceneData& { return flat[k % 5]; });
  std::printf("[crossval] %-34s %s\n", "moving instances occluded", occlusion.summary().c_str());
  EXPECT_EQ(occlusion.mismatched, 0u) << occlusion.summary();
  libs.embree->rtcReleaseScene(scenes[0]);
  libs.obvh->rtcReleaseScene(scenes[1]);
}

// --- User geometry --------------------------------------------------------------------------------

struct Sphere {
  float x, y, z, r;
  float vx = 0.f;  // moves along x by vx over the shutter (two time steps when not 0)
};

void sphereBounds(const RTCBoundsFunctionArguments* args) {
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  const float x = s.x + s.vx * float(args->timeStep);
  *args->bounds_o = RTCBounds{x - s.r, s.y - s.r, s.z - s.r, 0.f, x + s.r, s.y + s.r, s.z + s.r, 0.f};
}

// Nearest root of |o + t d - c|^2 = r^2 inside the segment, computed in double precision, with the
// sphere where it is at the ray's time.
bool sphereHit(const Sphere& s, const RTCRay& ray, float& tOut) {
  const double ox = ray.org_x - (s.x + s.vx * ray.time), oy = ray.org_y - s.y, oz = ray.org_z - s.z;
  const double a = double(ray.dir_x) * ray.dir_x + double(ray.dir_y) * ray.dir_y + double(ray.dir_z) * ray.dir_z;
  const double b = 2 * (ox * ray.dir_x + oy * ray.dir_y + oz * ray.dir_z);
  const double c = ox * ox + oy * oy + oz * oz - double(s.r) * s.r;
  const double disc = b * b - 4 * a * c;
  if (disc < 0) return false;
  for (double t : {(-b - std::sqrt(disc)) / (2 * a), (-b + std::sqrt(disc)) / (2 * a)})
    if (t > ray.tnear && t <= ray.tfar) {
      tOut = float(t);
      return true;
    }
  return false;
}

void sphereIntersect(const RTCIntersectFunctionNArguments* args) {
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  RTCRayHit* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
  ASSERT_EQ(args->N, 1u);
  float t;
  if (args->valid[0] != -1 || !sphereHit(s, rh->ray, t)) return;
  rh->ray.tfar = t;
  rh->hit.Ng_x = rh->ray.org_x + t * rh->ray.dir_x - (s.x + s.vx * rh->ray.time);
  rh->hit.Ng_y = rh->ray.org_y + t * rh->ray.dir_y - s.y;
  rh->hit.Ng_z = rh->ray.org_z + t * rh->ray.dir_z - s.z;
  rh->hit.u = rh->hit.v = 0.f;
  rh->hit.primID = args->primID;
  rh->hit.geomID = args->geomID;
  rh->hit.instID[0] = args->context->instID[0];
}

void sphereOccluded(const RTCOccludedFunctionNArguments* args) {
  const Sphere& s = static_cast<const Sphere*>(args->geometryUserPtr)[args->primID];
  RTCRay* ray = reinterpret_cast<RTCRay*>(args->ray);
  float t;
  if (args->valid[0] == -1 && sphereHit(s, *ray, t)) ray->tfar = -std::numeric_limits<float>::infinity();
}

// Spheres as user geometry (moving ones: two time steps, rays at random times).
void expectUserSpheresMatchEmbree(bool moving) {
  // Embree may call user callbacks with packets of N > 1 (for its own packet kernels); the
  // single-ray API used here calls them with N = 1 in both libraries.
  const LoadedLibraries& libs = libraries();
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  static std::vector<Sphere> spheres;
  spheres.clear();
  for (int k = 0; k < 400; ++k)  // on a grid so spheres never overlap: every hit is unambiguous
    spheres.push_back({float(k % 20) + 0.5f, float(k / 20) + 0.5f, 2.f * unit(rng), 0.1f + 0.35f * unit(rng),
                       moving ? 3.f : 0.f});
  RTCScene scenes[2];
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  for (int k = 0; k < 2; ++k) {
    scenes[k] = lib[k]->rtcNewScene(devices[k]);
    RTCGeometry g = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_USER);
    if (moving) lib[k]->rtcSetGeometryTimeStepCount(g, 2);
    lib[k]->rtcSetGeometryUserPrimitiveCount(g, unsigned(spheres.size()));
    lib[k]->rtcSetGeometryUserData(g, spheres.data());
    lib[k]->rtcSetGeometryBoundsFunction(g, sphereBounds, nullptr);
    lib[k]->rtcSetGeometryIntersectFunction(g, sphereIntersect);
    lib[k]->rtcSetGeometryOccludedFunction(g, sphereOccluded);
    lib[k]->rtcCommitGeometry(g);
    lib[k]->rtcAttachGeometry(scenes[k], g);
    lib[k]->rtcReleaseGeometry(g);
    lib[k]->rtcCommitScene(scenes[k]);
    ASSERT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::vector<RTCRay> rays = raysAround(-2.f, 22.f, kRays, 32);
  if (moving) assignRandomTimes(rays, 33);
  const std::vector<RTCRayHit> a = traceAll(*libs.embree, scenes[0], rays, &context);
  const std::vector<RTCRayHit> b = traceAll(*libs.obvh, scenes[1], rays, &context);
  size_t hits = 0, differ = 0, occlusionDiffers = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    const HitRecord ha = tools::toHitRecord(a[k]), hb = tools::toHitRecord(b[k]);
    hits += ha.hit();
    // Same callback code on the same ray: answers must be identical, bit for bit.
    if (ha.geomID != hb.geomID || ha.primID != hb.primID || (ha.hit() && std::memcmp(&a[k], &b[k], sizeof(RTCRayHit)) != 0))
      ++differ;
    RTCRay ra = rays[k], rb = rays[k];
    libs.embree->rtcOccluded1(scenes[0], &context, &ra);
    libs.obvh->rtcOccluded1(scenes[1], &context, &rb);
    occlusionDiffers += (ra.tfar != rb.tfar);
  }
  std::printf("[crossval] %-34s %zu rays, %zu hits, %zu differ, %zu occlusion answers differ\n",
              moving ? "moving user spheres" : "user spheres", rays.size(), hits, differ, occlusionDiffers);
  EXPECT_GT(hits, kRays / 20);
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(occlusionDiffers, 0u);
  libs.embree->rtcReleaseScene(scenes[0]);
  libs.obvh->rtcReleaseScene(scenes[1]);
}

TEST(CrossvalUserGeometry, SpheresMatchEmbree) { expectUserSpheresMatchEmbree(false); }

// Motion blur: the bounds callback is asked for every time step (Embree's timeStep argument).
TEST(CrossvalUserGeometry, MovingSpheresMatchEmbree) { expectUserSpheresMatchEmbree(true); }

// --- Filters ----------------------------------------------------------------------------------------

void rejectEveryThirdPrimitive(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] && RTCHitN_primID(args->hit, args->N, i) % 3 == 0) args->valid[i] = 0;
}

void rejectEvenPrimitives(const RTCFilterFunctionNArguments* args) {
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] && RTCHitN_primID(args->hit, args->N, i) % 2 == 0) args->valid[i] = 0;
}

// The judge has no filters: rejected primitives are collapsed to a point, keeping primIDs.
SceneData withoutRejected(SceneData scene, unsigned modulo) {
  for (MeshData& mesh : scene.meshes) {
    const uint32_t first = mesh.indices[0];
    for (size_t p = 0; p < mesh.primitiveCount(); ++p)
      if (p % modulo == 0)
        for (int c = 0; c < 3; ++c) mesh.indices[3 * p + c] = first;
  }
  return scene;
}

TEST(CrossvalFilters, GeometryAndContextFiltersMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  SceneData scene;
  scene.meshes.push_back(randomTriangleSoup(8000, 41));
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  RTCScene geometryFiltered[2], contextFiltered[2];
  for (int k = 0; k < 2; ++k) {
    geometryFiltered[k] = lib[k]->rtcNewScene(devices[k]);
    RTCGeometry g = addMesh(*lib[k], devices[k], geometryFiltered[k], scene.meshes[0]);
    lib[k]->rtcSetGeometryIntersectFilterFunction(g, rejectEveryThirdPrimitive);
    lib[k]->rtcSetGeometryOccludedFilterFunction(g, rejectEvenPrimitives);
    lib[k]->rtcCommitGeometry(g);
    lib[k]->rtcReleaseGeometry(g);
    lib[k]->rtcCommitScene(geometryFiltered[k]);
    contextFiltered[k] = lib[k]->rtcNewScene(devices[k]);
    lib[k]->rtcSetSceneFlags(contextFiltered[k], RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    lib[k]->rtcReleaseGeometry(addMesh(*lib[k], devices[k], contextFiltered[k], scene.meshes[0]));
    lib[k]->rtcCommitScene(contextFiltered[k]);
    ASSERT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
  }
  const std::vector<RTCRay> rays = raysAround(-0.2f, 1.2f, kRays, 42);
  RTCIntersectContext plain, filtering;
  rtcInitIntersectContext(&plain);
  rtcInitIntersectContext(&filtering);
  filtering.filter = rejectEveryThirdPrimitive;

  const SceneData judgeIntersect = withoutRejected(scene, 3), judgeOcclusion2 = withoutRejected(scene, 2);
  struct Case {
    const char* name;
    RTCScene* scenes;
    RTCIntersectContext* context;
  } cases[] = {{"geometry filter", geometryFiltered, &plain}, {"context filter", contextFiltered, &filtering}};
  for (const Case& c : cases) {
    const std::vector<RTCRayHit> a = traceAll(*libs.embree, c.scenes[0], rays, c.context);
    const std::vector<RTCRayHit> b = traceAll(*libs.obvh, c.scenes[1], rays, c.context);
    CrossvalCounts counts;
    size_t rejectedReported = 0;
    for (size_t k = 0; k < rays.size(); ++k) {
      counts.add(tools::compareHits(judgeIntersect, rays[k], tools::toHitRecord(a[k]), tools::toHitRecord(b[k])), rays[k]);
      if (b[k].hit.geomID != RTC_INVALID_GEOMETRY_ID && b[k].hit.primID % 3 == 0) ++rejectedReported;
    }
    std::printf("[crossval] %-34s %s\n", c.name, counts.summary().c_str());
    EXPECT_EQ(counts.mismatched, 0u) << counts.summary();
    EXPECT_EQ(rejectedReported, 0u);
  }
  CrossvalCounts occlusion;
  for (size_t k = 0; k < 30000; ++k) {
    RTCRay ra = rays[k], rb = rays[k];
    libs.embree->rtcOccluded1(geometryFiltered[0], &plain, &ra);
    libs.obvh->rtcOccluded1(geometryFiltered[1], &plain, &rb);
    const float hit = -std::numeric_limits<float>::infinity();
    judgeOcclusion(judgeOcclusion2, rays[k], ra.tfar == hit, rb.tfar == hit, occlusion);
  }
  std::printf("[crossval] %-34s %s\n", "occlusion filter", occlusion.summary().c_str());
  EXPECT_EQ(occlusion.mismatched, 0u) << occlusion.summary();
  for (int k = 0; k < 2; ++k) {
    lib[k]->rtcReleaseScene(geometryFiltered[k]);
    lib[k]->rtcReleaseScene(contextFiltered[k]);
  }
}

// --- Interpolation ---------------------------------------------------------------------------------

TEST(CrossvalInterpolate, TrianglesQuadsAndGridsMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  const MeshData meshes[3] = {randomTriangleSoup(200, 51), quadGrid(10, 0.5f, 52), gridPatches(12, 0.5f, 54)};
  std::mt19937 rng(53);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (const MeshData& mesh : meshes) {
    std::vector<float> attribute(mesh.vertexCount() * 4);
    for (float& a : attribute) a = unit(rng) * 10.f;
    RTCGeometry g[2];
    const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
    RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
    for (int k = 0; k < 2; ++k) {
      RTCScene scratch = lib[k]->rtcNewScene(devices[k]);
      g[k] = addMesh(*lib[k], devices[k], scratch, mesh);
      lib[k]->rtcSetGeometryVertexAttributeCount(g[k], 1);
      lib[k]->rtcSetSharedGeometryBuffer(g[k], RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT4,
                                         attribute.data(), 0, 16, mesh.vertexCount());
      lib[k]->rtcCommitGeometry(g[k]);
      lib[k]->rtcReleaseScene(scratch);
    }
    size_t compared = 0;
    for (int n = 0; n < 2000; ++n) {
      const unsigned prim = unsigned(rng() % mesh.primitiveCount());
      float u = unit(rng), v = unit(rng);
      // Also the borders of a grid and of its cells (u = 1 is left out: Embree reads past the grid).
      if (mesh.grid && n % 4 == 0) u = float(rng() % (mesh.grids[prim].width - 1u)) / float(mesh.grids[prim].width - 1u);
      if (mesh.grid && n % 4 == 1) v = float(rng() % (mesh.grids[prim].height - 1u)) / float(mesh.grids[prim].height - 1u);
      if (!mesh.quads && u + v > 1.f) u = 1.f - u, v = 1.f - v;
      for (RTCBufferType type : {RTC_BUFFER_TYPE_VERTEX, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE}) {
        const unsigned count = type == RTC_BUFFER_TYPE_VERTEX ? 3 : 4;
        float out[2][6][4];
        for (int k = 0; k < 2; ++k) {
          RTCInterpolateArguments args{g[k], prim, u, v, type, 0, out[k][0], out[k][1], out[k][2], out[k][3], out[k][4],
                                       out[k][5], count};
          lib[k]->rtcInterpolate(&args);
        }
        for (int s = 0; s < 6; ++s)
          for (unsigned c = 0; c < count; ++c)
            EXPECT_NEAR(out[0][s][c], out[1][s][c], 1e-4f * (1.f + std::fabs(out[0][s][c])))
                << (mesh.grid ? "grid" : mesh.quads ? "quad" : "triangle") << " prim " << prim << " u " << u << " v " << v << " part " << s;
        ++compared;
      }
    }
    EXPECT_EQ(compared, 4000u);
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
      lib[k]->rtcReleaseGeometry(g[k]);
    }
  }
}

// Motion blur: rtcInterpolate reads the vertex buffer of the time step its slot names.
TEST(CrossvalInterpolate, TimeStepSlotsMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  SceneData scene;
  scene.meshes.push_back(moving(quadGrid(8, 0.4f, 55), 3, 56));
  scene.meshes.push_back(moving(gridPatches(8, 0.4f, 57), 2, 58));
  const tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  const tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene);
  std::mt19937 rng(59);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t compared = 0;
  for (unsigned geomID = 0; geomID < 2; ++geomID) {
    const MeshData& mesh = scene.meshes[geomID];
    for (int n = 0; n < 300; ++n) {
      const unsigned prim = unsigned(rng() % mesh.primitiveCount()), slot = unsigned(rng() % mesh.timeStepCount());
      const float u = unit(rng), v = unit(rng);
      float out[2][3][3];
      const tools::CommittedScene* committed[2] = {&reference, &candidate};
      const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
      for (int k = 0; k < 2; ++k) {
        RTCInterpolateArguments args{committed[k]->geometry(geomID), prim, u, v, RTC_BUFFER_TYPE_VERTEX, slot, out[k][0],
                                     out[k][1], out[k][2], nullptr, nullptr, nullptr, 3};
        lib[k]->rtcInterpolate(&args);
      }
      for (int part = 0; part < 3; ++part)
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(out[0][part][c], out[1][part][c], 1e-4f * (1.f + std::fabs(out[0][part][c])))
              << "geometry " << geomID << " prim " << prim << " slot " << slot << " part " << part;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 600u);
  EXPECT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
}

}  // namespace
}  // namespace obvh::test
