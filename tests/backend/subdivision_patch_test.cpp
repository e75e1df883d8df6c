// The Catmull-Clark evaluator on its own: a regular patch is the bicubic B-spline of its control
// points, PIN_ALL gives the bilinear control mesh, affine invariance keeps a flat mesh flat, and a
// closed mesh's tessellation has no cracks (every edge between two of its triangles).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>

#include "subdiv/patch_eval.h"
#include "subdiv/subdiv_tessellation.h"

namespace obvh {
namespace {

struct Mesh {
  std::vector<double> xyz;
  SubdivMeshInput input;
};

void readXyz(const void* context, uint32_t vertex, double* out) {
  const Mesh& m = *static_cast<const Mesh*>(context);
  for (int k = 0; k < 3; ++k) out[k] = m.xyz[3 * vertex + k];
}

// A (n + 1) x (n + 1) grid of vertices with random heights, n x n quads.
Mesh bumpyGrid(int n, uint32_t seed) {
  Mesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> height(-0.5, 0.5);
  for (int r = 0; r <= n; ++r)
    for (int c = 0; c <= n; ++c) m.xyz.insert(m.xyz.end(), {double(c), double(r), height(rng)});
  for (uint32_t r = 0; r < uint32_t(n); ++r)
    for (uint32_t c = 0; c < uint32_t(n); ++c) {
      const uint32_t a = r * uint32_t(n + 1) + c;
      m.input.indices.insert(m.input.indices.end(), {a, a + 1, a + uint32_t(n) + 2, a + uint32_t(n) + 1});
      m.input.faceSizes.push_back(4);
    }
  m.input.vertexCount = uint32_t((n + 1) * (n + 1));
  return m;
}

double bspline(int i, double t) {
  const double s = 1.0 - t;
  const double w[4] = {s * s * s / 6.0, (3 * t * t * t - 6 * t * t + 4) / 6.0, (-3 * t * t * t + 3 * t * t + 3 * t + 1) / 6.0,
                       t * t * t / 6.0};
  return w[i];
}

TEST(SubdivisionPatch, RegularFaceIsTheBicubicBSplineOfItsControlPoints) {
  Mesh m = bumpyGrid(3, 1);
  const SubdivTopology topology(m.input);
  const uint32_t centre = 4;  // the middle face of 3 x 3: every corner of valence 4
  for (double u : {0.0, 0.3, 0.5, 0.91, 1.0})
    for (double v : {0.0, 0.2, 0.77, 1.0}) {
      const PatchPoint p = evaluatePatch(facePatch(topology, centre, 0, 3, readXyz, &m), u, v);
      double expected[3] = {0, 0, 0};
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
          for (int k = 0; k < 3; ++k) expected[k] += bspline(r, v) * bspline(c, u) * m.xyz[3 * (r * 4 + c) + k];
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.P[k], expected[k], 1e-12) << u << " " << v;
      EXPECT_NEAR(p.dPdu[0], 1.0, 1e-12);  // x = c: the B-spline reproduces linear functions
      EXPECT_NEAR(p.dPdv[1], 1.0, 1e-12);
    }
}

TEST(SubdivisionPatch, DerivativesMatchFiniteDifferencesNearAnExtraordinaryVertex) {
  Mesh m;  // a cube: every vertex of valence 3
  m.xyz = {-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, 1, -1, 1, 1, 1, -1, 1, 1};
  m.input.indices = {0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 0, 3, 7, 4, 4, 7, 6, 5, 0, 1, 2, 3};
  m.input.faceSizes.assign(6, 4);
  m.input.vertexCount = 8;
  const SubdivTopology topology(m.input);
  const LocalPatch patch = facePatch(topology, 0, 0, 3, readXyz, &m);
  const double h = 1e-6;
  for (double u : {0.05, 0.3, 0.6})
    for (double v : {0.07, 0.45}) {
      const PatchPoint p = evaluatePatch(patch, u, v);
      const PatchPoint pu = evaluatePatch(patch, u + h, v), pv = evaluatePatch(patch, u, v + h);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(p.dPdu[k], (pu.P[k] - p.P[k]) / h, 1e-4);
        EXPECT_NEAR(p.dPdv[k], (pv.P[k] - p.P[k]) / h, 1e-4);
      }
    }
}

TEST(SubdivisionPatch, PinAllGivesTheBilinearControlMesh) {
  Mesh m = bumpyGrid(4, 2);
  m.input.boundary = SubdivBoundary::PinAll;
  const SubdivTopology topology(m.input);
  for (uint32_t face : {0u, 5u, 15u}) {
    const uint32_t* q = &m.input.indices[4 * face];
    for (double u : {0.1, 0.5, 0.8})
      for (double v : {0.25, 0.6}) {
        const PatchPoint p = evaluatePatch(facePatch(topology, face, 0, 3, readXyz, &m), u, v);
        for (int k = 0; k < 3; ++k) {
          const double bilinear = (1 - u) * (1 - v) * m.xyz[3 * q[0] + k] + u * (1 - v) * m.xyz[3 * q[1] + k] +
                                  u * v * m.xyz[3 * q[2] + k] + (1 - u) * v * m.xyz[3 * q[3] + k];
          EXPECT_NEAR(p.P[k], bilinear, 1e-9) << "face " << face;
        }
      }
  }
}

// A flat mesh of triangles, quads and a pentagon (extraordinary vertices, boundary corners)
// stays in its plane: subdivision rules are affine combinations.
TEST(SubdivisionPatch, FlatMeshesStayFlat) {
  Mesh m;
  m.xyz = {0, 0, 0, 2, 0, 0, 3, 1, 0, 2, 2, 0, 0, 2, 0, 1, 1, 0, 4, 2.5, 0, 1, 3, 0};
  m.input.indices = {0, 1, 5, 1, 2, 3, 5, 3, 4, 5, 4, 0, 5, 2, 6, 3, 3, 6, 7, 4};
  m.input.faceSizes = {3, 4, 3, 3, 3, 4};
  m.input.vertexCount = 8;
  const SubdivTopology topology(m.input);
  const SubdivTessellation t = tessellateSubdivision(topology, readXyz, &m, nullptr, 5.f);
  ASSERT_FALSE(t.vertices.empty());
  for (const Vec3f& p : t.vertices) EXPECT_NEAR(p.z, 0.f, 1e-6f);
}

TEST(SubdivisionTessellation, ClosedMeshesHaveNoCracks) {
  Mesh m;  // a cube of quads with one face split into two triangles
  m.xyz = {-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, 1, -1, 1, 1, 1, -1, 1, 1};
  m.input.indices = {0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 0, 3, 7, 4, 4, 7, 6, 5, 0, 1, 2, 0, 2, 3};
  m.input.faceSizes = {4, 4, 4, 4, 4, 3, 3};
  m.input.vertexCount = 8;
  const SubdivTopology topology(m.input);
  for (float rate : {1.f, 3.f, 6.5f}) {
    const SubdivTessellation t = tessellateSubdivision(topology, readXyz, &m, nullptr, rate);
    // Every triangle edge, by its end points' positions, is shared by exactly two triangles
    // (degenerate triangles of stitched edges excepted).
    std::map<std::tuple<float, float, float, float, float, float>, int> edges;
    auto key = [](const Vec3f& a, const Vec3f& b) {
      const bool less = std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
      const Vec3f& p = less ? a : b;
      const Vec3f& q = less ? b : a;
      return std::make_tuple(p.x, p.y, p.z, q.x, q.y, q.z);
    };
    for (size_t c = 0; c < t.cells.size(); ++c) {
      const uint32_t* k = &t.cellCorners[4 * c];
      const int tris[2][3] = {{0, 1, 3}, {2, 3, 1}};
      const auto same = [](const Vec3f& a, const Vec3f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
      for (const auto& tri : tris) {
        const Vec3f p[3] = {t.vertices[k[tri[0]]], t.vertices[k[tri[1]]], t.vertices[k[tri[2]]]};
        if (same(p[0], p[1]) || same(p[1], p[2]) || same(p[2], p[0])) continue;
        for (int e = 0; e < 3; ++e) ++edges[key(p[e], p[(e + 1) % 3])];
      }
    }
    size_t bad = 0;
    for (const auto& [edge, count] : edges) bad += count != 2;
    EXPECT_EQ(bad, 0u) << "rate " << rate << ": " << edges.size() << " edges";
  }
}

}  // namespace
}  // namespace obvh
