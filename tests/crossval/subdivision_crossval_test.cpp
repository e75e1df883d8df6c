// Catmull-Clark subdivision surfaces (RTC_GEOMETRY_TYPE_SUBDIVISION) through obvh and Debian's
// Embree. On closed meshes without creases Embree's tessellation points lie on the exact limit
// surface, as obvh's do, so hits must agree to float rounding: the same face, t, (u, v) (Embree
// stores grid (u, v) in 16 bits, hence 1e-4) and Ng. Where the mesh has boundaries or creases
// Embree approximates some patches (measured: up to ~1e-3 of the size, inside the faces), so those
// meshes are held to that distance instead. A face-border tie (both hits on the border of their
// faces, at the same t) may name either face.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "crossval_harness.h"
#include "ray_generation.h"

namespace obvh::test {
namespace {

struct SubdivMesh {
  std::string name;
  std::vector<float> vertices;  // x, y, z
  std::vector<uint32_t> faces, indices;
  std::vector<uint32_t> edgeCreases, vertexCreases;
  std::vector<float> edgeCreaseWeights, vertexCreaseWeights, levels;
  std::vector<float> laterVertices;  // motion blur: the vertices at time 1 (empty: still)
  float rate = -1.f;  // < 0: Embree's default
  int mode = -1;      // < 0: Embree's default (smooth boundary)
  float size() const {
    float lo = 1e30f, hi = -1e30f;
    for (float c : vertices) lo = std::min(lo, c), hi = std::max(hi, c);
    return hi - lo;
  }
};

SubdivMesh cube() {
  SubdivMesh m;
  m.name = "cube";
  m.vertices = {-1, -1, -1, 1, -1, -1, 1, -1, 1, -1, -1, 1, -1, 1, -1, 1, 1, -1, 1, 1, 1, -1, 1, 1};
  m.indices = {0, 4, 5, 1, 1, 5, 6, 2, 2, 6, 7, 3, 0, 3, 7, 4, 4, 7, 6, 5, 0, 1, 2, 3};
  m.faces.assign(6, 4);
  return m;
}

SubdivMesh triangleCube() {
  SubdivMesh m = cube();
  m.name = "triangle cube";
  m.indices = {1, 4, 5, 0, 4, 1, 2, 5, 6, 1, 5, 2, 3, 6, 7, 2, 6, 3, 4, 3, 7, 0, 3, 4, 5, 7, 6, 4, 7, 5, 3, 1, 2, 0, 1, 3};
  m.faces.assign(12, 3);
  return m;
}

// A pentagonal prism, its caps raised into roofs: faces of 5, 4 and 3 vertices.
SubdivMesh prism() {
  SubdivMesh m;
  m.name = "pentagonal prism";
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < 5; ++k) {
      const double a = 2.0 * M_PI * k / 5.0;
      m.vertices.insert(m.vertices.end(), {float(1.3 * std::cos(a)), float(1.3 * std::sin(a)), ring ? 1.f : -1.f});
    }
  m.vertices.insert(m.vertices.end(), {0.f, 0.f, 1.8f});
  for (uint32_t k = 0; k < 5; ++k) {
    const uint32_t n = (k + 1) % 5;
    m.indices.insert(m.indices.end(), {k, n, 5 + n, 5 + k});
    m.faces.push_back(4);
  }
  m.indices.insert(m.indices.end(), {4, 3, 2, 1, 0});  // the bottom cap, seen from below
  m.faces.push_back(5);
  for (uint32_t k = 0; k < 5; ++k) {
    m.indices.insert(m.indices.end(), {5 + k, 5 + (k + 1) % 5, 10});
    m.faces.push_back(3);
  }
  return m;
}

// A bumpy open 6 x 6 grid of quads: boundary edges and corners.
SubdivMesh openGrid() {
  SubdivMesh m;
  m.name = "open grid";
  for (int r = 0; r <= 6; ++r)
    for (int c = 0; c <= 6; ++c)
      m.vertices.insert(m.vertices.end(), {float(c) - 3.f, float(r) - 3.f, 0.4f * std::sin(1.3f * r + 0.7f * c)});
  for (uint32_t r = 0; r < 6; ++r)
    for (uint32_t c = 0; c < 6; ++c) {
      const uint32_t a = r * 7 + c;
      m.indices.insert(m.indices.end(), {a, a + 1, a + 8, a + 7});
      m.faces.push_back(4);
    }
  return m;
}

// Per-edge levels from 1 to 5, equal on both half-edges of an edge.
void assignEdgeLevels(SubdivMesh& m) {
  size_t k = 0;
  for (uint32_t n : m.faces) {
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t a = m.indices[k + i], b = m.indices[k + (i + 1) % n];
      if (a > b) std::swap(a, b);
      m.levels.push_back(float(1 + (a * 7 + b * 13) % 5));
    }
    k += n;
  }
}

template <typename T>
void setBuffer(const RtcLibrary& lib, RTCGeometry g, RTCBufferType type, RTCFormat format, size_t itemSize,
               const std::vector<T>& data, size_t components) {
  if (data.empty()) return;
  void* p = lib.rtcSetNewGeometryBuffer(g, type, 0, format, itemSize, data.size() / components);
  std::memcpy(p, data.data(), data.size() * sizeof(T));
}

RTCScene commit(const RtcLibrary& lib, RTCDevice device, const SubdivMesh& m) {
  RTCScene scene = lib.rtcNewScene(device);
  RTCGeometry g = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SUBDIVISION);
  setBuffer(lib, g, RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, 12, m.vertices, 3);
  if (!m.laterVertices.empty()) {
    lib.rtcSetGeometryTimeStepCount(g, 2);
    void* p = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT3, 12, m.laterVertices.size() / 3);
    std::memcpy(p, m.laterVertices.data(), m.laterVertices.size() * sizeof(float));
  }
  setBuffer(lib, g, RTC_BUFFER_TYPE_FACE, RTC_FORMAT_UINT, 4, m.faces, 1);
  setBuffer(lib, g, RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT, 4, m.indices, 1);
  setBuffer(lib, g, RTC_BUFFER_TYPE_EDGE_CREASE_INDEX, RTC_FORMAT_UINT2, 8, m.edgeCreases, 2);
  setBuffer(lib, g, RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT, RTC_FORMAT_FLOAT, 4, m.edgeCreaseWeights, 1);
  setBuffer(lib, g, RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX, RTC_FORMAT_UINT, 4, m.vertexCreases, 1);
  setBuffer(lib, g, RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT, RTC_FORMAT_FLOAT, 4, m.vertexCreaseWeights, 1);
  setBuffer(lib, g, RTC_BUFFER_TYPE_LEVEL, RTC_FORMAT_FLOAT, 4, m.levels, 1);
  if (m.rate >= 0.f) lib.rtcSetGeometryTessellationRate(g, m.rate);
  if (m.mode >= 0) lib.rtcSetGeometrySubdivisionMode(g, 0, RTCSubdivisionMode(m.mode));
  // The vertex positions again as a vertex attribute, for interpolation.
  lib.rtcSetGeometryVertexAttributeCount(g, 1);
  void* a = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, 12, m.vertices.size() / 3);
  std::memcpy(a, m.vertices.data(), m.vertices.size() * sizeof(float));
  lib.rtcCommitGeometry(g);
  lib.rtcAttachGeometry(scene, g);
  lib.rtcReleaseGeometry(g);
  lib.rtcCommitScene(scene);
  EXPECT_EQ(lib.rtcGetDeviceError(device), RTC_ERROR_NONE) << lib.label << " " << m.name;
  return scene;
}

RTCRayHit trace(const RtcLibrary& lib, RTCScene scene, const RTCRay& ray) {
  RTCRayHit rh{};
  rh.ray = ray;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  lib.rtcIntersect1(scene, &context, &rh);
  return rh;
}

// On the border of its face: u or v (in the face's own, or its subpatch's, parametrization) at 0 or 1.
bool onFaceBorder(const RTCHit& h, uint32_t faceSize) {
  double u = h.u, v = h.v;
  if (faceSize != 4) u = 2.0 * (0.5 * u - std::floor(0.5 * u)) - 0.5, v = 2.0 * (0.5 * v - std::floor(0.5 * v)) - 0.5;
  constexpr double kNear = 2e-3;
  return u < kNear || u > 1.0 - kNear || v < kNear || v > 1.0 - kNear;
}

// On an edge or the diagonal of a tessellation cell (a tie between two triangles, whose normals
// differ): with the uniform rate, a quad's grid has ceil(rate) cells a side, a subpatch ceil(rate / 2).
bool onCellBorder(const RTCHit& h, uint32_t faceSize, float rate) {
  double u = h.u, v = h.v;
  if (faceSize != 4) u = 2.0 * (0.5 * u - std::floor(0.5 * u)) - 0.5, v = 2.0 * (0.5 * v - std::floor(0.5 * v)) - 0.5;
  const float level = rate < 0.f ? 2.f : rate;
  const double cells = std::max(1.0, std::ceil(faceSize == 4 ? level : 0.5 * level));
  const double fu = u * cells - std::floor(u * cells), fv = v * cells - std::floor(v * cells);
  constexpr double kNear = 1e-3;
  return fu < kNear || fu > 1.0 - kNear || fv < kNear || fv > 1.0 - kNear || std::fabs(fu + fv - 1.0) < kNear;
}

struct Tolerance {
  double distance;  // between the surfaces along the normal, relative to the mesh's size
  double uv;       // absolute
  double normal;   // 1 - cos of the angle between the normals
  double grazing;  // |cos| between ray and surface below which one library may hit and the other miss
  bool embreeCracksAtCreases;
};

std::vector<RTCRay> raysAt(const SubdivMesh& m, size_t count, uint32_t seed) {
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (size_t i = 0; i < m.vertices.size(); ++i) lo[i % 3] = std::min(lo[i % 3], m.vertices[i]), hi[i % 3] = std::max(hi[i % 3], m.vertices[i]);
  return tools::randomRays(tools::SceneBox{{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}, count, seed);
}

// Traces the rays through both libraries; returns the number of hits and counts mismatches.
size_t compareHits(const SubdivMesh& m, const std::vector<RTCRay>& rays, const Tolerance& tol, size_t& mismatches,
                   std::string& example) {
  const LoadedLibraries& libs = libraries();
  RTCScene reference = commit(*libs.embree, libs.embreeDevice, m);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice, m);
  std::vector<uint32_t> faceSize(m.faces);
  const double size = m.size();
  size_t hits = 0;
  mismatches = 0;
  for (const RTCRay& ray : rays) {
    const RTCRayHit e = trace(*libs.embree, reference, ray), o = trace(*libs.obvh, candidate, ray);
    const bool eHit = e.hit.geomID != RTC_INVALID_GEOMETRY_ID, oHit = o.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    std::string why;
    if (eHit != oHit) {
      // Only a ray grazing the surface may touch it in one tessellation and miss the other.
      const RTCRayHit& h = eHit ? e : o;
      const double dl = std::sqrt(ray.dir_x * ray.dir_x + ray.dir_y * ray.dir_y + ray.dir_z * ray.dir_z);
      const double nl = std::sqrt(h.hit.Ng_x * h.hit.Ng_x + h.hit.Ng_y * h.hit.Ng_y + h.hit.Ng_z * h.hit.Ng_z);
      const double c = (ray.dir_x * h.hit.Ng_x + ray.dir_y * h.hit.Ng_y + ray.dir_z * h.hit.Ng_z) / (dl * nl);
      // Where Embree approximates the patches on both sides of a crease, its two grids need not meet
      // (measured: rays through the crease of the creased cube miss Embree's surface); obvh's are
      // evaluated on the limit surface and share their edge points.
      const bool embreeCrack = tol.embreeCracksAtCreases && oHit && onFaceBorder(o.hit, faceSize.at(o.hit.primID));
      if (std::fabs(c) > tol.grazing && !embreeCrack)
        why = std::string(eHit ? "only Embree hits" : "only obvh hits") + " (cos " + std::to_string(c) + ", face " +
              std::to_string(h.hit.primID) + " at (" + std::to_string(h.hit.u) + ", " + std::to_string(h.hit.v) + "))";
    } else if (eHit) {
      ++hits;
      // How far apart the two surfaces are where the ray meets them: the depth difference along the normal.
      const double dl = std::sqrt(ray.dir_x * ray.dir_x + ray.dir_y * ray.dir_y + ray.dir_z * ray.dir_z);
      const double nl = std::sqrt(e.hit.Ng_x * e.hit.Ng_x + e.hit.Ng_y * e.hit.Ng_y + e.hit.Ng_z * e.hit.Ng_z);
      const double cosine = (ray.dir_x * e.hit.Ng_x + ray.dir_y * e.hit.Ng_y + ray.dir_z * e.hit.Ng_z) / (dl * nl);
      const double apart = std::fabs(double(e.ray.tfar) - double(o.ray.tfar)) * dl * std::fabs(cosine) / size;
      if (apart > tol.distance) why = "surfaces " + std::to_string(apart) + " of the size apart";
      if (e.hit.primID != o.hit.primID) {
        if (!(onFaceBorder(e.hit, faceSize.at(e.hit.primID)) && onFaceBorder(o.hit, faceSize.at(o.hit.primID))))
          why = "face " + std::to_string(e.hit.primID) + " vs " + std::to_string(o.hit.primID);
      } else if (std::fabs(e.hit.u - o.hit.u) > tol.uv || std::fabs(e.hit.v - o.hit.v) > tol.uv) {
        why = "face " + std::to_string(e.hit.primID) + " uv (" + std::to_string(e.hit.u) + ", " + std::to_string(e.hit.v) + ") vs (" + std::to_string(o.hit.u) +
              ", " + std::to_string(o.hit.v) + ")";
      } else {
        const double en = std::sqrt(e.hit.Ng_x * e.hit.Ng_x + e.hit.Ng_y * e.hit.Ng_y + e.hit.Ng_z * e.hit.Ng_z);
        const double on = std::sqrt(o.hit.Ng_x * o.hit.Ng_x + o.hit.Ng_y * o.hit.Ng_y + o.hit.Ng_z * o.hit.Ng_z);
        const double c = (e.hit.Ng_x * o.hit.Ng_x + e.hit.Ng_y * o.hit.Ng_y + e.hit.Ng_z * o.hit.Ng_z) / (en * on);
        if (1.0 - c > tol.normal && !onCellBorder(e.hit, faceSize.at(e.hit.primID), m.rate))
          why = "Ng differs (cos " + std::to_string(c) + ")";
      }
    }
    if (why.empty()) continue;
    if (++mismatches <= (getenv("SUBDIV_EXAMPLES") ? 40 : 3)) example += "\n  " + m.name + ": " + why;
  }
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
  return hits;
}

void expectMatch(SubdivMesh m, const Tolerance& tol, size_t rayCount = 20000) {
  size_t mismatches = 0;
  std::string example;
  const size_t hits = compareHits(m, raysAt(m, rayCount, 17), tol, mismatches, example);
  std::printf("%s (rate %g, %s levels, mode %d): %zu rays, %zu hits, %zu mismatches\n", m.name.c_str(), m.rate,
              m.levels.empty() ? "no" : "per-edge", m.mode, rayCount, hits, mismatches);
  EXPECT_GT(hits, rayCount / 20) << m.name;
  EXPECT_EQ(mismatches, 0u) << example;
}

constexpr Tolerance kExact{1e-5, 2e-4, 1e-4, 0.02, false};

TEST(CrossvalSubdivision, ClosedMeshesMatchEmbree) {
  for (SubdivMesh m : {cube(), triangleCube(), prism()})
    for (float rate : {-1.f, 1.f, 2.5f, 7.f}) {
      m.rate = rate;
      expectMatch(m, kExact);
    }
}

TEST(CrossvalSubdivision, PerEdgeLevelsOfQuadMeshesMatchEmbree) {
  SubdivMesh m = cube();
  assignEdgeLevels(m);
  expectMatch(m, kExact);
}

// Motion blur: two time steps, rays at random times; the surface at a time is the blend of the
// steps' surfaces (the limit surface is linear in the control points).
TEST(CrossvalSubdivision, MovingMeshesMatchEmbree) {
  for (SubdivMesh m : {cube(), prism()}) {
    m.name += " (moving)";
    m.rate = 3.f;
    for (size_t i = 0; i < m.vertices.size(); ++i)
      m.laterVertices.push_back(m.vertices[i] * (i % 3 == 1 ? 0.6f : 1.1f) + (i % 3 == 0 ? 0.4f : 0.f));
    std::vector<RTCRay> rays = raysAt(m, 20000, 19);
    assignRandomTimes(rays, 29);
    size_t mismatches = 0;
    std::string example;
    const size_t hits = compareHits(m, rays, kExact, mismatches, example);
    std::printf("%s: %zu rays, %zu hits, %zu mismatches\n", m.name.c_str(), rays.size(), hits, mismatches);
    EXPECT_GT(hits, rays.size() / 20);
    EXPECT_EQ(mismatches, 0u) << example;
  }
}

// Embree approximates patches at boundaries and creases (inside the faces, by up to ~1e-3 of the
// size, measured); obvh evaluates the exact limit surface there.
TEST(CrossvalSubdivision, BoundariesCreasesAndModesStayWithinEmbreesApproximation) {
  const Tolerance approximate{2e-3, 2e-2, 2e-2, 0.02, true};
  for (int mode : {-1, int(RTC_SUBDIVISION_MODE_PIN_CORNERS), int(RTC_SUBDIVISION_MODE_PIN_BOUNDARY),
                   int(RTC_SUBDIVISION_MODE_PIN_ALL), int(RTC_SUBDIVISION_MODE_NO_BOUNDARY)}) {
    SubdivMesh m = openGrid();
    m.mode = mode;
    m.rate = 4.f;
    expectMatch(m, approximate);
  }
  SubdivMesh creased = cube();
  creased.name = "cube with a creased face and a sharp corner";
  creased.edgeCreases = {0, 1, 1, 2, 2, 3, 3, 0};
  creased.edgeCreaseWeights.assign(4, INFINITY);
  creased.vertexCreases = {6};
  creased.vertexCreaseWeights = {INFINITY};
  creased.rate = 6.f;
  expectMatch(creased, approximate);
}

// rtcInterpolate of the vertex buffer and of a vertex attribute (the same positions): values and
// first derivatives at random points of every face.
TEST(CrossvalSubdivision, InterpolationMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  size_t compared = 0;
  for (const SubdivMesh& m : {cube(), triangleCube(), prism()}) {
    RTCScene reference = commit(*libs.embree, libs.embreeDevice, m);
    RTCScene candidate = commit(*libs.obvh, libs.obvhDevice, m);
    RTCGeometry eg = libs.embree->rtcGetGeometry(reference, 0), og = libs.obvh->rtcGetGeometry(candidate, 0);
    for (uint32_t face = 0; face < m.faces.size(); ++face)
      for (int k = 0; k < 40; ++k) {
        float u = unit(rng), v = unit(rng);
        if (m.faces[face] != 4) {  // a subpatch, in Embree's encoding
          const int sub = int(unit(rng) * float(m.faces[face])) % int(m.faces[face]);
          u = 2.f * float(sub % 4) + 0.5f + u, v = 2.f * float(sub / 4) + 0.5f + v;
        }
        for (RTCBufferType type : {RTC_BUFFER_TYPE_VERTEX, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE}) {
          float out[2][3][3];
          for (int lib = 0; lib < 2; ++lib) {
            RTCInterpolateArguments args{};
            args.geometry = lib == 0 ? eg : og;
            args.primID = face, args.u = u, args.v = v, args.bufferType = type, args.bufferSlot = 0;
            args.P = out[lib][0], args.dPdu = out[lib][1], args.dPdv = out[lib][2], args.valueCount = 3;
            (lib == 0 ? libs.embree : libs.obvh)->rtcInterpolate(&args);
          }
          for (int s = 0; s < 3; ++s)
            for (int c = 0; c < 3; ++c)
              EXPECT_NEAR(out[0][s][c], out[1][s][c], 2e-4 * (s == 0 ? 1.f : 4.f))
                  << m.name << " face " << face << " (" << u << ", " << v << ") output " << s << " component " << c;
          ++compared;
        }
      }
    libs.embree->rtcReleaseScene(reference);
    libs.obvh->rtcReleaseScene(candidate);
  }
  std::printf("%zu interpolations compared\n", compared);
}

// The half-edge queries on a mesh with boundaries: every answer equal to Embree's.
TEST(CrossvalSubdivision, HalfEdgesMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  SubdivMesh m = prism();
  m.faces.pop_back();  // open the roof: boundary edges
  m.indices.resize(m.indices.size() - 3);
  RTCScene reference = commit(*libs.embree, libs.embreeDevice, m);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice, m);
  RTCGeometry eg = libs.embree->rtcGetGeometry(reference, 0), og = libs.obvh->rtcGetGeometry(candidate, 0);
  for (uint32_t f = 0; f < m.faces.size(); ++f)
    EXPECT_EQ(libs.embree->rtcGetGeometryFirstHalfEdge(eg, f), libs.obvh->rtcGetGeometryFirstHalfEdge(og, f));
  for (uint32_t h = 0; h < m.indices.size(); ++h) {
    EXPECT_EQ(libs.embree->rtcGetGeometryFace(eg, h), libs.obvh->rtcGetGeometryFace(og, h)) << h;
    EXPECT_EQ(libs.embree->rtcGetGeometryNextHalfEdge(eg, h), libs.obvh->rtcGetGeometryNextHalfEdge(og, h)) << h;
    EXPECT_EQ(libs.embree->rtcGetGeometryPreviousHalfEdge(eg, h), libs.obvh->rtcGetGeometryPreviousHalfEdge(og, h)) << h;
    EXPECT_EQ(libs.embree->rtcGetGeometryOppositeHalfEdge(eg, 0, h), libs.obvh->rtcGetGeometryOppositeHalfEdge(og, 0, h))
        << h;
  }
  EXPECT_EQ(libs.embree->rtcGetDeviceError(libs.embreeDevice), RTC_ERROR_NONE);
  EXPECT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

}  // namespace
}  // namespace obvh::test
