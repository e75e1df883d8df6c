// Hard numerical cases on obvh alone, through the public API: geometry far from the origin and at
// extreme scales, degenerate triangles, special ray values, NaN and infinity. Failures print rays
// in hex floats so they can be replayed.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "obvh_scene.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

std::string hex(const RTCRay& r) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tnear=%a tfar=%a", r.org_x, r.org_y, r.org_z,
                r.dir_x, r.dir_y, r.dir_z, r.tnear, r.tfar);
  return buf;
}

// Rays from the centre of a closed mesh through every vertex and edge point: none may escape.
size_t leaksFromCenter(const ObvhMode& mode, const MeshData& mesh, const float center[3], int pointsPerEdge,
                       std::string& firstLeak) {
  ObvhScene scene({mesh}, mode.config, mode.flags);
  size_t leaks = 0;
  for (size_t prim = 0; prim < mesh.primitiveCount(); ++prim)
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = mesh.indices[3 * prim + c], b = mesh.indices[3 * prim + (c + 1) % 3];
      for (int k = 0; k < pointsPerEdge; ++k) {
        const float w = float(k) / float(pointsPerEdge);
        float dir[3];
        for (int axis = 0; axis < 3; ++axis)
          dir[axis] = (1 - w) * mesh.vertices[3 * a + axis] + w * mesh.vertices[3 * b + axis] - center[axis];
        const RTCRay ray = makeRay(center, dir);
        if (scene.intersect(ray).hit.geomID == RTC_INVALID_GEOMETRY_ID || !scene.occluded(ray))
          if (leaks++ == 0) firstLeak = hex(ray);
      }
    }
  return leaks;
}

// Every case runs in every obvh mode; the leak tests only in the modes that promise watertightness.
class HardCases : public ::testing::TestWithParam<ObvhMode> {
 protected:
  ObvhScene sceneOf(const std::vector<MeshData>& meshes) const {
    return ObvhScene(meshes, GetParam().config, GetParam().flags);
  }
};
class HardCasesWatertight : public HardCases {};

TEST_P(HardCasesWatertight, ClosedMeshesFarFromTheOriginDoNotLeak) {
  for (float offset : {1e4f, 1e5f, 1e6f, 1e7f}) {
    const float radius = offset * 1e-3f;  // keeps the triangles many ulps wide at that magnitude
    const float center[3] = {offset, -offset, 0.5f * offset};
    std::string first;
    EXPECT_EQ(leaksFromCenter(GetParam(), icosphere(3, radius, center), center, 4, first), 0u) << "offset " << offset << ": " << first;
  }
}

TEST_P(HardCasesWatertight, ClosedMeshesAtExtremeScalesDoNotLeak) {
  for (float scale : {1e-4f, 1e4f}) {
    const float center[3] = {0.3f * scale, 0.1f * scale, -0.2f * scale};
    std::string first;
    EXPECT_EQ(leaksFromCenter(GetParam(), icosphere(3, scale, center), center, 4, first), 0u) << "scale " << scale << ": " << first;
  }
}

TEST_P(HardCases, DegenerateTrianglesNeverHitAndWriteNoNaN) {
  MeshData mesh;
  mesh.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0,      // a good triangle (prim 0), z = 0
                   0, 0, 1, 0, 0, 1, 1, 1, 1,      // repeated vertex (prim 1), z = 1
                   0, 0, 2, 0.5f, 0.5f, 2, 1, 1, 2,  // collinear (prim 2), z = 2
                   0.3f, 0.3f, 3, 0.3f, 0.3f, 3, 0.3f, 0.3f, 3};  // a point (prim 3), z = 3
  mesh.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11};
  const ObvhScene scene = sceneOf({mesh});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(-0.2f, 1.2f);
  for (int i = 0; i < 20000; ++i) {
    const float org[3] = {unit(rng), unit(rng), 5.f}, dir[3] = {unit(rng) * 0.1f, unit(rng) * 0.1f, -1.f};
    const RTCRayHit rh = scene.intersect(makeRay(org, dir));
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    EXPECT_EQ(rh.hit.primID, 0u) << hex(rh.ray);
    EXPECT_TRUE(std::isfinite(rh.ray.tfar) && std::isfinite(rh.hit.u) && std::isfinite(rh.hit.v) &&
                std::isfinite(rh.hit.Ng_x) && std::isfinite(rh.hit.Ng_y) && std::isfinite(rh.hit.Ng_z))
        << hex(rh.ray);
  }
  // Rays exactly through the degenerate primitives' points.
  const float throughPoint[3] = {0.3f, 0.3f, 5.f}, down[3] = {0.f, 0.f, -1.f};
  EXPECT_EQ(scene.intersect(makeRay(throughPoint, down)).hit.primID, 0u);
}

TEST_P(HardCases, TinyAndHugeTrianglesInOneScene) {
  MeshData tiny = randomTriangleSoup(2000, 2);
  const float offset[3] = {0.f, 0.f, 0.f};
  transformMesh(tiny, 1e-5f, offset);  // triangles of about 1e-7 .. 1e-5
  MeshData huge;
  huge.vertices = {-1e6f, -1e6f, -1.f, 1e6f, -1e6f, -1.f, 0.f, 1e6f, -1.f};
  huge.indices = {0, 1, 2};
  const ObvhScene scene = sceneOf({tiny, huge});
  // Rays aimed at the tiny triangles' centroids hit them (before the huge plane behind them).
  size_t tinyHits = 0, planeHits = 0;
  for (size_t prim = 0; prim < tiny.primitiveCount(); ++prim) {
    float c[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int axis = 0; axis < 3; ++axis) c[axis] += tiny.vertices[3 * tiny.indices[3 * prim + k] + axis] / 3.f;
    const float org[3] = {c[0], c[1], 1e-4f}, dir[3] = {0.f, 0.f, -1.f};
    const RTCRayHit rh = scene.intersect(makeRay(org, dir));
    ASSERT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << hex(rh.ray);
    (rh.hit.geomID == 0 ? tinyHits : planeHits)++;
  }
  // A centroid may lie behind another tiny triangle; it may never fall through to the plane
  // unless it really misses every tiny triangle, which a centroid ray cannot.
  EXPECT_EQ(planeHits, 0u);
  EXPECT_EQ(tinyHits, tiny.primitiveCount());
}

TEST_P(HardCases, SpecialDirectionComponents) {
  const float lo[3] = {-1.f, -1.f, -1.f}, hi[3] = {1.f, 1.f, 1.f};
  const ObvhScene scene = sceneOf({box(lo, hi, false)});
  const float denormal = std::numeric_limits<float>::denorm_min();
  const float components[] = {0.f, -0.f, denormal, -denormal, 1e-30f};
  size_t rays = 0;
  for (float a : components)
    for (float b : components) {
      // From inside the closed box every ray must hit, whatever its tiny components are.
      const float org[3] = {0.25f, -0.5f, 0.1f};
      for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.f, -1.f}) {
          float dir[3];
          dir[axis] = sign;
          dir[(axis + 1) % 3] = a;
          dir[(axis + 2) % 3] = b;
          const RTCRayHit rh = scene.intersect(makeRay(org, dir));
          EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << hex(rh.ray);
          EXPECT_TRUE(scene.occluded(makeRay(org, dir))) << hex(rh.ray);
          ++rays;
        }
    }
  EXPECT_EQ(rays, 150u);
  // Axis-parallel rays running exactly inside a face's plane, from outside, along the face.
  const float alongFace[3] = {-5.f, 1.f, 0.2f}, plusX[3] = {1.f, 0.f, 0.f};
  EXPECT_NE(scene.intersect(makeRay(alongFace, plusX)).hit.geomID, RTC_INVALID_GEOMETRY_ID)
      << "a ray in the plane of a face still crosses the box's other faces";
}

// Rays that do not move along x (or y), with the origin exactly on the cube's x (or y) bounding
// plane, running inside a face's plane to the edge where the far face meets it. Every box of the
// BVH on the way to that edge has the same bounding plane, so the slab of a zero direction
// component must include its boundary (signed zeros both ways: -0 picks the planes of a negative
// direction).
TEST_P(HardCases, ZeroDirectionComponentsWithTheOriginOnABoundingPlane) {
  const float lo[3] = {-1.f, -1.f, -1.f}, hi[3] = {1.f, 1.f, 1.f};
  const ObvhScene scene = sceneOf({cubeGrid(16, lo, hi)});  // 3,072 triangles: a tree of nodes, not one leaf
  size_t rays = 0;
  for (int still = 0; still < 2; ++still)  // the axis the ray does not move along: x or y
    for (float onPlane : {lo[still], hi[still]})
      for (float zero : {0.f, -0.f})
        for (float along : {1.f, -1.f}) {
          float org[3] = {0.3f, -0.2f, 0.1f}, dir[3] = {0.f, 0.f, along};
          org[still] = onPlane;
          dir[still] = zero;
          dir[1 - still] = 0.f;
          const RTCRayHit rh = scene.intersect(makeRay(org, dir));
          EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << hex(rh.ray);
          EXPECT_FLOAT_EQ(rh.ray.tfar, 1.f - along * 0.1f) << hex(rh.ray);
          EXPECT_TRUE(scene.occluded(makeRay(org, dir))) << hex(rh.ray);
          ++rays;
        }
  EXPECT_EQ(rays, 16u);
}

// The same for flat grids, whose boxes keep the world axes in every layout (no oriented box is
// smaller than a planar rectangle's): rays along a grid's normal, down its outer border lines, hit
// its boundary edges, and the boxes they must enter have their bounding planes exactly at the rays'
// origins, where a zero direction component makes the distance to that plane 0 * inf = NaN. Grids
// facing each axis, so that the still axis is each row of the box tests in turn (a NaN in the last
// row is the one no later row can cover up).
TEST_P(HardCasesWatertight, ZeroDirectionComponentsAlongAFlatGridsBorder) {
  size_t rays = 0;
  for (int normal = 0; normal < 3; ++normal) {
    const MeshData flat = quadGrid(32, 0.f, 1);  // 2,048 triangles in z = 0 over [0,1]^2
    MeshData grid = flat;
    const int a = (normal + 1) % 3, b = (normal + 2) % 3;  // the axes the grid spans
    for (size_t v = 0; v < flat.vertexCount(); ++v) {
      grid.vertices[3 * v + size_t(normal)] = 0.f;
      grid.vertices[3 * v + size_t(a)] = flat.vertices[3 * v];
      grid.vertices[3 * v + size_t(b)] = flat.vertices[3 * v + 1];
    }
    const ObvhScene scene = sceneOf({grid});
    for (int still : {a, b})
      for (float onBorder : {0.f, 1.f})
        for (float zero : {0.f, -0.f})
          for (float across : {0.13f, 0.41f, 0.77f}) {
            float org[3], dir[3];
            org[normal] = 2.f, dir[normal] = -1.f;
            org[a] = org[b] = across;
            dir[a] = dir[b] = -zero;
            org[still] = onBorder;
            dir[still] = zero;
            const RTCRayHit rh = scene.intersect(makeRay(org, dir));
            EXPECT_NE(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID) << hex(rh.ray);
            EXPECT_EQ(rh.ray.tfar, 2.f) << hex(rh.ray);
            EXPECT_TRUE(scene.occluded(makeRay(org, dir))) << hex(rh.ray);
            ++rays;
          }
  }
  EXPECT_EQ(rays, 72u);
}

TEST_P(HardCases, SegmentBoundaries) {
  MeshData tri;
  tri.vertices = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  tri.indices = {0, 1, 2};
  const ObvhScene scene = sceneOf({tri});
  const float org[3] = {0.2f, 0.2f, 1.f}, down[3] = {0.f, 0.f, -1.f};
  // Hits lie in (tnear, tfar]: exactly at tfar counts, exactly at tnear does not (as in Embree).
  EXPECT_NE(scene.intersect(makeRay(org, down, 0.f, 1.f)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(scene.intersect(makeRay(org, down, 1.f, kInf)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(scene.intersect(makeRay(org, down, 1.f, 1.f)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_EQ(scene.intersect(makeRay(org, down, 2.f, 0.5f)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  EXPECT_FALSE(scene.occluded(makeRay(org, down, 1.f, 1.f)));
  // Origin on the surface: with tnear = 0 the surface itself (t = 0) is not hit.
  const float onSurface[3] = {0.2f, 0.2f, 0.f};
  EXPECT_EQ(scene.intersect(makeRay(onSurface, down)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
  const float up[3] = {0.f, 0.f, 1.f};
  EXPECT_EQ(scene.intersect(makeRay(onSurface, up)).hit.geomID, RTC_INVALID_GEOMETRY_ID);
}

TEST_P(HardCases, NanAndInfinityNeverCrashAndNeverHit) {
  MeshData good = randomTriangleSoup(1000, 3);
  MeshData bad = good;  // same triangles with poisoned vertices: every one is skipped at build
  for (size_t i = 0; i < bad.vertices.size(); i += 7)
    bad.vertices[i] = (i / 7) % 2 ? std::numeric_limits<float>::quiet_NaN() : kInf;
  const ObvhScene scene = sceneOf({good, bad});
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float org[3] = {0.5f, 0.5f, 2.f}, dir[3] = {0.f, 0.f, -1.f};
  const float nanOrg[3] = {nan, 0.5f, 2.f}, nanDir[3] = {0.f, nan, -1.f}, infDir[3] = {kInf, 0.f, -1.f};
  for (const RTCRay& ray : {makeRay(nanOrg, dir), makeRay(org, nanDir), makeRay(org, infDir),
                            makeRay(org, dir, nan, kInf), makeRay(org, dir, 0.f, nan)}) {
    EXPECT_EQ(scene.intersect(ray).hit.geomID, RTC_INVALID_GEOMETRY_ID) << hex(ray);
    EXPECT_FALSE(scene.occluded(ray)) << hex(ray);
  }
  // Poisoned primitives are never reported; the valid ones still are.
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const float o[3] = {unit(rng), unit(rng), 2.f};
    const RTCRayHit rh = scene.intersect(makeRay(o, dir));
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    ++hits;
    if (rh.hit.geomID == 1) {
      const uint32_t* idx = &bad.indices[3 * rh.hit.primID];
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis)
          EXPECT_TRUE(std::isfinite(bad.vertices[3 * idx[k] + axis])) << "a primitive with a NaN/inf vertex was hit";
    }
  }
  EXPECT_GT(hits, 1000u);
  EXPECT_EQ(rtcGetDeviceError(scene.device()), RTC_ERROR_NONE);
}

INSTANTIATE_TEST_SUITE_P(EveryMode, HardCases, ::testing::ValuesIn(kEveryMode), modeName);
INSTANTIATE_TEST_SUITE_P(WatertightModes, HardCasesWatertight, ::testing::ValuesIn(kWatertightModes), modeName);

}  // namespace
}  // namespace obvh::test
