#include "hit_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace obvh::tools {
namespace {

struct D3 {
  double x, y, z;
};
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 crossD(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dotD(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double lengthD(D3 a) { return std::sqrt(dotD(a, a)); }

D3 vertex(const MeshData& mesh, uint32_t index) {
  return {mesh.vertices[3 * index], mesh.vertices[3 * index + 1], mesh.vertices[3 * index + 2]};
}

struct TriangleHitD {
  bool insidePlaneHit = false;
  double t = 0.0;
  double b[3] = {0, 0, 0};  // barycentric weights of v0, v1, v2
};

TriangleHitD intersectTriangleD(D3 org, D3 dir, D3 v0, D3 v1, D3 v2) {
  TriangleHitD out;
  const D3 e1 = sub(v1, v0), e2 = sub(v2, v0);
  const D3 p = crossD(dir, e2);
  const double det = dotD(e1, p);
  if (det == 0.0 || !std::isfinite(det)) return out;
  const D3 s = sub(org, v0);
  const double u = dotD(s, p) / det;
  const D3 q = crossD(s, e1);
  const double v = dotD(dir, q) / det;
  out.t = dotD(e2, q) / det;
  out.b[0] = 1.0 - u - v;
  out.b[1] = u;
  out.b[2] = v;
  out.insidePlaneHit = true;
  return out;
}

// Signed distance (positive inside) from the hit point to the triangle's boundary, in world units.
double edgeDistance(const TriangleHitD& h, D3 v0, D3 v1, D3 v2) {
  const D3 corners[3] = {v0, v1, v2};
  const double twiceArea = lengthD(crossD(sub(v1, v0), sub(v2, v0)));
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const double opposite = lengthD(sub(corners[(i + 2) % 3], corners[(i + 1) % 3]));
    const double height = opposite > 0.0 ? twiceArea / opposite : 0.0;
    best = std::min(best, h.b[i] * height);
  }
  return best;
}

double coordinateMagnitude(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID) {
  double m = std::max({std::fabs(ray.org_x), std::fabs(ray.org_y), std::fabs(ray.org_z)});
  const MeshData& mesh = scene.meshes.at(geomID);
  const int corners = mesh.quads ? 4 : 3;
  for (int c = 0; c < corners; ++c) {
    const D3 v = vertex(mesh, mesh.indices[size_t(primID) * corners + c]);
    m = std::max({m, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  }
  return m;
}

bool nearlyEqual(float a, float b, float relative) {
  return std::fabs(a - b) <= relative * std::max({std::fabs(a), std::fabs(b), 1e-30f});
}

bool sameValues(const HitRecord& a, const HitRecord& b, const CompareTolerance& tol, std::string& why) {
  char buf[256];
  if (!nearlyEqual(a.t, b.t, tol.tRelative)) {
    std::snprintf(buf, sizeof buf, "t differs: %.9g vs %.9g", a.t, b.t);
    why = buf;
    return false;
  }
  if (std::fabs(a.u - b.u) > tol.uvAbsolute || std::fabs(a.v - b.v) > tol.uvAbsolute) {
    std::snprintf(buf, sizeof buf, "u,v differ: (%.7g, %.7g) vs (%.7g, %.7g)", a.u, a.v, b.u, b.v);
    why = buf;
    return false;
  }
  const double na = std::sqrt(double(a.Ng[0]) * a.Ng[0] + double(a.Ng[1]) * a.Ng[1] + double(a.Ng[2]) * a.Ng[2]);
  for (int k = 0; k < 3; ++k)
    if (std::fabs(double(a.Ng[k]) - b.Ng[k]) > tol.normalRelative * na) {
      std::snprintf(buf, sizeof buf, "Ng differs: (%g, %g, %g) vs (%g, %g, %g)", a.Ng[0], a.Ng[1], a.Ng[2], b.Ng[0],
                    b.Ng[1], b.Ng[2]);
      why = buf;
      return false;
    }
  return true;
}

std::string describeHit(const char* who, const HitRecord& h) {
  if (!h.hit()) return std::string(who) + " missed";
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s hit geom %u prim %u at t=%.9g", who, h.geomID, h.primID, h.t);
  return buf;
}

}  // namespace

ExactHit intersectExact(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID) {
  ExactHit best;
  const MeshData& mesh = scene.meshes.at(geomID);
  const D3 org{ray.org_x, ray.org_y, ray.org_z}, dir{ray.dir_x, ray.dir_y, ray.dir_z};
  const int corners = mesh.quads ? 4 : 3;
  const uint32_t* idx = &mesh.indices[size_t(primID) * corners];
  D3 tris[2][3];
  int triCount = 1;
  if (mesh.quads) {  // Embree's split: (v0, v1, v3) and (v2, v3, v1)
    const D3 q[4] = {vertex(mesh, idx[0]), vertex(mesh, idx[1]), vertex(mesh, idx[2]), vertex(mesh, idx[3])};
    tris[0][0] = q[0], tris[0][1] = q[1], tris[0][2] = q[3];
    tris[1][0] = q[2], tris[1][1] = q[3], tris[1][2] = q[1];
    triCount = 2;
  } else {
    tris[0][0] = vertex(mesh, idx[0]), tris[0][1] = vertex(mesh, idx[1]), tris[0][2] = vertex(mesh, idx[2]);
  }
  best.edgeDistance = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < triCount; ++k) {
    const TriangleHitD h = intersectTriangleD(org, dir, tris[k][0], tris[k][1], tris[k][2]);
    if (!h.insidePlaneHit) continue;
    const double d = edgeDistance(h, tris[k][0], tris[k][1], tris[k][2]);
    if (d > best.edgeDistance) {
      best.edgeDistance = d;
      best.t = h.t;
      const bool secondQuadHalf = mesh.quads && k == 1;
      best.u = secondQuadHalf ? 1.0 - h.b[1] : h.b[1];
      best.v = secondQuadHalf ? 1.0 - h.b[2] : h.b[2];
      best.hit = d >= 0.0 && h.t > ray.tnear && h.t <= ray.tfar;
    }
  }
  return best;
}

Comparison compareHits(const SceneData& scene, const RTCRay& ray, const HitRecord& reference,
                       const HitRecord& candidate, const CompareTolerance& tol) {
  Comparison result;
  if (!reference.hit() && !candidate.hit()) return result;
  if (reference.hit() && candidate.hit() && reference.geomID == candidate.geomID &&
      reference.primID == candidate.primID) {
    std::string why;
    if (sameValues(reference, candidate, tol, why)) return result;
    // Same primitive, different values: the double-precision answer decides. If obvh is within
    // tolerance of it, Embree's rounding (e.g. on a grazing ray) caused the difference.
    const ExactHit exact = intersectExact(scene, ray, candidate.geomID, candidate.primID);
    HitRecord truth = candidate;
    truth.t = float(exact.t);
    truth.u = float(exact.u);
    truth.v = float(exact.v);
    std::string candidateWhy;
    const bool candidateExact = sameValues(truth, candidate, tol, candidateWhy);
    result = {candidateExact ? Verdict::Ambiguous : Verdict::Mismatch,
              why + (candidateExact ? " (obvh agrees with the double-precision answer)" : " (obvh: " + candidateWhy + " from the double-precision answer)")};
    return result;
  }

  // Different primitives, or a hit against a miss: examine each reported hit in double precision.
  const std::string what = describeHit("embree", reference) + ", " + describeHit("obvh", candidate);
  bool ambiguous = false;
  double exactT[2] = {0, 0};
  const HitRecord* hits[2] = {&reference, &candidate};
  for (int k = 0; k < 2; ++k) {
    if (!hits[k]->hit()) continue;
    const ExactHit exact = intersectExact(scene, ray, hits[k]->geomID, hits[k]->primID);
    exactT[k] = exact.t;
    const double magnitude = coordinateMagnitude(scene, ray, hits[k]->geomID, hits[k]->primID);
    const double edgeTolerance = tol.edgeUlps * magnitude * std::numeric_limits<float>::epsilon() * 0.5;
    const double tScale = std::max(std::fabs(exact.t), 1e-30);
    const bool nearEdge = std::fabs(exact.edgeDistance) <= edgeTolerance;
    const bool nearSegmentEnd = std::fabs(exact.t - ray.tnear) <= tol.tRelative * tScale ||
                                std::fabs(exact.t - ray.tfar) <= tol.tRelative * tScale;
    if (nearEdge || nearSegmentEnd) ambiguous = true;
  }
  if (reference.hit() && candidate.hit() &&
      std::fabs(exactT[0] - exactT[1]) <= tol.tRelative * std::max({std::fabs(exactT[0]), std::fabs(exactT[1]), 1e-30}))
    ambiguous = true;  // equally distant surfaces: either answer is a correct closest hit
  result.verdict = ambiguous ? Verdict::Ambiguous : Verdict::Mismatch;
  result.reason = what;
  return result;
}

std::string describeRay(const RTCRay& r) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tnear=%a tfar=%a mask=0x%x", r.org_x, r.org_y,
                r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tnear, r.tfar, r.mask);
  return buf;
}

}  // namespace obvh::tools
