// rtcPointQuery through obvh and Debian's Embree: a closest-point search (the callback computes the
// exact distance to each candidate and shrinks the radius) must find the same nearest primitive,
// including through instances (which exercises the callback context's transforms and IDs).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "crossval_harness.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

struct Closest {
  double distance = std::numeric_limits<double>::infinity();
  unsigned geomID = RTC_INVALID_GEOMETRY_ID, primID = RTC_INVALID_GEOMETRY_ID, instID = RTC_INVALID_GEOMETRY_ID;
  unsigned calls = 0;
};

struct QueryData {
  const std::vector<MeshData>* meshes;  // child meshes by geomID (the instanced scene's)
  const std::vector<MeshData>* topMeshes;
  Closest closest;
};

using P = std::array<double, 3>;
P sub(P a, P b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dotp(P a, P b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Closest point on triangle abc to p (Ericson's region test), in double precision.
double distanceToTriangle(P p, P a, P b, P c) {
  const P ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dotp(ab, ap), d2 = dotp(ac, ap);
  auto dist = [&](P q) { return std::sqrt(dotp(sub(p, q), sub(p, q))); };
  auto lerp = [](P x, P y, double t) { return P{x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1]), x[2] + t * (y[2] - x[2])}; };
  if (d1 <= 0 && d2 <= 0) return dist(a);
  const P bp = sub(p, b);
  const double d3 = dotp(ab, bp), d4 = dotp(ac, bp);
  if (d3 >= 0 && d4 <= d3) return dist(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return dist(lerp(a, b, d1 / (d1 - d3)));
  const P cp = sub(p, c);
  const double d5 = dotp(ab, cp), d6 = dotp(ac, cp);
  if (d6 >= 0 && d5 <= d6) return dist(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return dist(lerp(a, c, d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return dist(lerp(b, c, (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return dist({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

bool closestPointCallback(RTCPointQueryFunctionArguments* args) {
  QueryData& data = *static_cast<QueryData*>(args->userPtr);
  ++data.closest.calls;
  const bool instanced = args->context->instStackSize > 0;
  const MeshData& mesh = (instanced ? *data.meshes : *data.topMeshes).at(args->geomID);
  const float* m = args->context->inst2world[0];  // column major 4x4
  // Embree's convention: under a similarity transform the query arrives in instance space (and
  // distances are measured there); otherwise it is in world space and primitives are moved there.
  const bool localSpace = instanced && args->similarityScale > 0.f;
  auto world = [&](uint32_t index) {
    const double x = mesh.vertices[3 * index], y = mesh.vertices[3 * index + 1], z = mesh.vertices[3 * index + 2];
    if (!instanced || localSpace) return P{x, y, z};
    return P{m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
             m[2] * x + m[6] * y + m[10] * z + m[14]};
  };
  const P p{args->query->x, args->query->y, args->query->z};
  double d = std::numeric_limits<double>::infinity();
  if (mesh.grid) {  // the nearest of the grid's cells
    const RTCGrid& g = mesh.grids.at(args->primID);
    for (uint32_t y = 0; y + 1 < g.height; ++y)
      for (uint32_t x = 0; x + 1 < g.width; ++x) {
        const uint32_t i = g.startVertexID + y * g.stride + x;
        d = std::min({d, distanceToTriangle(p, world(i), world(i + 1), world(i + g.stride)),
                      distanceToTriangle(p, world(i + 1 + g.stride), world(i + g.stride), world(i + 1))});
      }
  } else {
    const int corners = mesh.quads ? 4 : 3;
    const uint32_t* idx = &mesh.indices[size_t(args->primID) * corners];
    d = distanceToTriangle(p, world(idx[0]), world(idx[1]), world(idx[2]));
    if (mesh.quads) d = std::min(d, distanceToTriangle(p, world(idx[0]), world(idx[2]), world(idx[3])));
  }
  const double worldDistance = localSpace ? d * args->similarityScale : d;
  if (worldDistance >= data.closest.distance || d > args->query->radius) return false;
  data.closest = {worldDistance, args->geomID, args->primID,
                  instanced ? args->context->instID[0] : RTC_INVALID_GEOMETRY_ID, data.closest.calls};
  args->query->radius = float(d);
  return true;
}

TEST(CrossvalPointQuery, ClosestPointMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const std::vector<MeshData> child = {randomTriangleSoup(2000, 61), quadGrid(12, 0.3f, 62), gridPatches(14, 0.4f, 65)};
  const std::vector<MeshData> top = {randomTriangleSoup(3000, 63)};
  const float xfm[2][12] = {{0.5f, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 2.f, 0.f, 0.f},   // similarity
                            {0.f, 1.f, 0, -0.7f, 0.f, 0, 0, 0, 0.4f, -1.5f, 0.5f, 0.f}};  // rotation + anisotropic scale
  RTCScene scenes[2];
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  for (int k = 0; k < 2; ++k) {
    RTCScene childScene = lib[k]->rtcNewScene(devices[k]);
    for (const MeshData& mesh : child) {
      tools::SceneData one;
      one.meshes = {mesh};
      RTCGeometry g = lib[k]->rtcNewGeometry(
          devices[k], mesh.grid ? RTC_GEOMETRY_TYPE_GRID : mesh.quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
      lib[k]->rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.vertices.data(), 0, 12,
                                         mesh.vertexCount());
      if (mesh.grid)
        lib[k]->rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, mesh.grids.data(), 0,
                                           sizeof(RTCGrid), mesh.primitiveCount());
      else
        lib[k]->rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, mesh.quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                           mesh.indices.data(), 0, mesh.quads ? 16 : 12, mesh.primitiveCount());
      lib[k]->rtcCommitGeometry(g);
      lib[k]->rtcAttachGeometry(childScene, g);
      lib[k]->rtcReleaseGeometry(g);
    }
    lib[k]->rtcCommitScene(childScene);
    scenes[k] = lib[k]->rtcNewScene(devices[k]);
    RTCGeometry g = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_TRIANGLE);  // geomID 0
    lib[k]->rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, top[0].vertices.data(), 0, 12,
                                       top[0].vertexCount());
    lib[k]->rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, top[0].indices.data(), 0, 12,
                                       top[0].primitiveCount());
    lib[k]->rtcCommitGeometry(g);
    lib[k]->rtcAttachGeometry(scenes[k], g);
    lib[k]->rtcReleaseGeometry(g);
    for (const auto& m : xfm) {  // geomIDs 1 and 2
      RTCGeometry inst = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_INSTANCE);
      lib[k]->rtcSetGeometryInstancedScene(inst, childScene);
      lib[k]->rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m);
      lib[k]->rtcCommitGeometry(inst);
      lib[k]->rtcAttachGeometry(scenes[k], inst);
      lib[k]->rtcReleaseGeometry(inst);
    }
    lib[k]->rtcCommitScene(scenes[k]);
    lib[k]->rtcReleaseScene(childScene);
    ASSERT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE) << lib[k]->label;
  }

  std::mt19937 rng(64);
  std::uniform_real_distribution<float> unit(-2.5f, 3.5f);
  size_t queries = 0, found = 0, differ = 0, ties = 0, onGrid = 0;
  for (int q = 0; q < 3000; ++q) {
    Closest result[2];
    const float radii[3] = {std::numeric_limits<float>::infinity(), 0.3f, 20.f};
    const float radius = radii[q % 3];
    const float point[3] = {unit(rng), unit(rng), unit(rng) * 0.5f};
    for (int k = 0; k < 2; ++k) {
      QueryData data{&child, &top, {}};
      RTCPointQuery query{point[0], point[1], point[2], 0.f, radius};
      RTCPointQueryContext context;
      rtcInitPointQueryContext(&context);
      lib[k]->rtcPointQuery(scenes[k], &query, &context, closestPointCallback, &data);
      result[k] = data.closest;
      EXPECT_EQ(context.instStackSize, 0u);
    }
    ++queries;
    found += result[0].geomID != RTC_INVALID_GEOMETRY_ID;
    onGrid += result[0].instID != RTC_INVALID_GEOMETRY_ID && result[0].geomID == 2;  // the child's grid mesh
    const bool same = result[0].geomID == result[1].geomID && result[0].primID == result[1].primID &&
                      result[0].instID == result[1].instID;
    if (same) {
      EXPECT_DOUBLE_EQ(result[0].distance, result[1].distance);
      continue;
    }
    // Two primitives at the same distance (shared edges or vertices) are both correct answers.
    if (std::fabs(result[0].distance - result[1].distance) <= 1e-6 * (1.0 + result[0].distance)) {
      ++ties;
      continue;
    }
    ++differ;
    ADD_FAILURE() << "query " << q << ": embree found geom " << result[0].geomID << " prim " << result[0].primID
                  << " inst " << result[0].instID << " at " << result[0].distance << ", obvh geom " << result[1].geomID
                  << " prim " << result[1].primID << " inst " << result[1].instID << " at " << result[1].distance;
    if (differ > 5) break;
  }
  std::printf("[crossval] %-34s %zu queries, %zu found something (%zu a grid), %zu ties, %zu differ\n",
              "point query closest", queries, found, onGrid, ties, differ);
  EXPECT_GT(found, queries / 2);
  EXPECT_GT(onGrid, 0u);
  EXPECT_EQ(differ, 0u);
  for (int k = 0; k < 2; ++k) lib[k]->rtcReleaseScene(scenes[k]);
}

}  // namespace
}  // namespace obvh::test
