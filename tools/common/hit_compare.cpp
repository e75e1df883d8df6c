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

// A vertex where it is at `time` (motion blur); false when the mesh is not there at that time.
bool vertex(const MeshData& mesh, uint64_t index, float time, D3& out) {
  float v[3];
  if (!mesh.vertexAt(index, time, v)) return false;
  out = {v[0], v[1], v[2]};
  return true;
}

// One triangle of a primitive with the map from its barycentric (u, v) to the primitive's
// parameterisation in Embree's convention: u' = uOffset + uScale * (flipped ? 1 - u : u), same for v.
struct PrimitiveTriangle {
  D3 v[3];
  bool flipped = false;
  double uOffset = 0.0, vOffset = 0.0, uScale = 1.0, vScale = 1.0;
};

// Triangles split from a quad (v0, v1, v2, v3) as Embree splits quads and grid cells: (v0, v1, v3)
// and (v2, v3, v1), the second with flipped (u, v).
void addQuadTriangles(const D3 q[4], std::vector<PrimitiveTriangle>& out, PrimitiveTriangle cell = {}) {
  PrimitiveTriangle first = cell, second = cell;
  first.v[0] = q[0], first.v[1] = q[1], first.v[2] = q[3];
  second.v[0] = q[2], second.v[1] = q[3], second.v[2] = q[1];
  second.flipped = true;
  out.push_back(first);
  out.push_back(second);
}

// The triangles a primitive consists of at a ray's time: one (triangle), two (quad) or two per
// cell (grid, whose (u, v) spans the whole grid); none when a moving mesh is not there then.
std::vector<PrimitiveTriangle> primitiveTriangles(const MeshData& mesh, unsigned primID, float time) {
  std::vector<PrimitiveTriangle> out;
  if (!mesh.presentAt(time)) return out;
  const auto vertexAt = [&](uint64_t index) {
    D3 v;
    vertex(mesh, index, time, v);
    return v;
  };
  if (mesh.grid) {
    const RTCGrid& g = mesh.grids.at(primID);
    if (g.width < 2 || g.height < 2) return out;
    const auto at = [&](uint32_t x, uint32_t y) { return vertexAt(uint64_t(g.startVertexID) + uint64_t(y) * g.stride + x); };
    for (uint32_t y = 0; y + 1 < g.height; ++y)
      for (uint32_t x = 0; x + 1 < g.width; ++x) {
        const D3 q[4] = {at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)};
        PrimitiveTriangle cell;
        cell.uScale = 1.0 / (g.width - 1), cell.vScale = 1.0 / (g.height - 1);
        cell.uOffset = x * cell.uScale, cell.vOffset = y * cell.vScale;
        addQuadTriangles(q, out, cell);
      }
    return out;
  }
  const int corners = mesh.quads ? 4 : 3;
  const uint32_t* idx = &mesh.indices.at(size_t(primID) * corners);
  if (mesh.quads) {
    const D3 q[4] = {vertexAt(idx[0]), vertexAt(idx[1]), vertexAt(idx[2]), vertexAt(idx[3])};
    addQuadTriangles(q, out);
  } else {
    PrimitiveTriangle t;
    t.v[0] = vertexAt(idx[0]), t.v[1] = vertexAt(idx[1]), t.v[2] = vertexAt(idx[2]);
    out.push_back(t);
  }
  return out;
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

// Distance between the infinite line org + s*dir and the segment [a, b]. Unlike barycentric edge
// distances, this stays meaningful for grazing rays, whose plane intersection is ill-conditioned.
double lineSegmentDistance(D3 org, D3 dir, D3 a, D3 b) {
  const D3 v = sub(b, a), w = sub(org, a);
  const double dd = dotD(dir, dir), dv = dotD(dir, v), vv = dotD(v, v), dw = dotD(dir, w), vw = dotD(v, w);
  const double denom = dd * vv - dv * dv;
  double t = denom > 1e-300 * dd * vv ? (dd * vw - dv * dw) / denom : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double s = (dv * t - dw) / dd;  // closest line parameter for that segment point
  const D3 between{w.x + s * dir.x - t * v.x, w.y + s * dir.y - t * v.y, w.z + s * dir.z - t * v.z};
  return lengthD(between);
}

double coordinateMagnitude(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID) {
  double m = std::max({std::fabs(ray.org_x), std::fabs(ray.org_y), std::fabs(ray.org_z)});
  for (const PrimitiveTriangle& tri : primitiveTriangles(scene.meshes.at(geomID), primID, ray.time))
    for (const D3& v : tri.v) m = std::max({m, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  return m;
}

bool nearlyEqual(double a, double b, double relative) {
  return std::fabs(a - b) <= relative * std::max({std::fabs(a), std::fabs(b), 1e-30});
}

// tSlack and uvSlack widen the tolerances by what rounding the inputs to float alone can cause.
bool sameValues(const HitRecord& a, const HitRecord& b, const CompareTolerance& tol, std::string& why,
                double tSlack = 0.0, double uvSlack = 0.0) {
  char buf[256];
  if (std::fabs(double(a.t) - b.t) > tSlack && !nearlyEqual(a.t, b.t, tol.tRelative)) {
    std::snprintf(buf, sizeof buf, "t differs: %.9g vs %.9g", a.t, b.t);
    why = buf;
    return false;
  }
  if (std::fabs(a.u - b.u) > tol.uvAbsolute + uvSlack || std::fabs(a.v - b.v) > tol.uvAbsolute + uvSlack) {
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
  char buf[200];
  std::snprintf(buf, sizeof buf, "%s hit geom %u prim %u at t=%.9g u=%.7g v=%.7g", who, h.geomID, h.primID, h.t, h.u,
                h.v);
  return buf;
}

// How a part of a primitive relates to the ray, after accounting for rounding.
struct PartJudgement {
  bool borderline = false;  // within tolerance of an edge, a vertex or an end of the segment
  bool clearHit = false;    // hit well inside the primitive and well inside (tnear, tfar]
};

PartJudgement judge(const ExactPart& part, const RTCRay& ray, double edgeTolerance, const CompareTolerance& tol) {
  PartJudgement j;
  const double tScale = std::max(std::fabs(part.t), 1e-30);
  const bool nearEdge = part.lineToEdges <= edgeTolerance;
  const bool nearEnds = std::fabs(part.t - ray.tnear) <= tol.tRelative * tScale ||
                        std::fabs(part.t - ray.tfar) <= tol.tRelative * tScale;
  const bool inside = part.planeHit && part.edgeDistance > 0.0;
  const bool inSegment = part.t > ray.tnear && part.t <= ray.tfar;
  j.borderline = nearEdge || (inside && nearEnds);
  j.clearHit = inside && inSegment && !j.borderline;
  return j;
}

// A position error of edgeTolerance (float inputs, transforms) moves the hit along the ray by that
// much over cos(angle): no float answer can be held to a tighter distance than this.
double distanceSlack(const ExactPart& part, const RTCRay& ray, double edgeTolerance) {
  const double dirLength =
      std::sqrt(double(ray.dir_x) * ray.dir_x + double(ray.dir_y) * ray.dir_y + double(ray.dir_z) * ray.dir_z);
  return edgeTolerance / (dirLength * std::max(part.cosine, 1e-6));
}

double edgeToleranceFor(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID,
                        const CompareTolerance& tol) {
  return tol.edgeUlps * coordinateMagnitude(scene, ray, geomID, primID) * std::numeric_limits<float>::epsilon() * 0.5;
}

}  // namespace

std::vector<ExactPart> intersectExact(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID) {
  const D3 org{ray.org_x, ray.org_y, ray.org_z}, dir{ray.dir_x, ray.dir_y, ray.dir_z};
  std::vector<ExactPart> parts;
  for (const PrimitiveTriangle& piece : primitiveTriangles(scene.meshes.at(geomID), primID, ray.time)) {
    const D3* tri = piece.v;
    ExactPart part;
    part.lineToEdges = std::min({lineSegmentDistance(org, dir, tri[0], tri[1]), lineSegmentDistance(org, dir, tri[1], tri[2]),
                                 lineSegmentDistance(org, dir, tri[2], tri[0])});
    const D3 normal = crossD(sub(tri[1], tri[0]), sub(tri[2], tri[0]));
    const double twiceArea = lengthD(normal);
    part.cosine = twiceArea > 0.0 ? std::fabs(dotD(normal, dir)) / (twiceArea * lengthD(dir)) : 0.0;
    part.minHeight = twiceArea / std::max({lengthD(sub(tri[1], tri[0])), lengthD(sub(tri[2], tri[1])),
                                           lengthD(sub(tri[0], tri[2])), 1e-300});
    const TriangleHitD h = intersectTriangleD(org, dir, tri[0], tri[1], tri[2]);
    if (h.insidePlaneHit && std::isfinite(h.t)) {
      part.planeHit = true;
      part.t = h.t;
      part.edgeDistance = edgeDistance(h, tri[0], tri[1], tri[2]);
      part.u = piece.uOffset + piece.uScale * (piece.flipped ? 1.0 - h.b[1] : h.b[1]);
      part.v = piece.vOffset + piece.vScale * (piece.flipped ? 1.0 - h.b[2] : h.b[2]);
    }
    parts.push_back(part);
  }
  return parts;
}

Comparison compareHits(const SceneData& scene, const RTCRay& ray, const HitRecord& reference,
                       const HitRecord& candidate, const CompareTolerance& tol) {
  Comparison result;
  if (!reference.hit() && !candidate.hit()) return result;
  std::string why;
  const bool samePrimitive = reference.hit() && candidate.hit() && reference.geomID == candidate.geomID &&
                             reference.primID == candidate.primID;
  if (samePrimitive && sameValues(reference, candidate, tol, why)) return result;
  if (!samePrimitive) why = "different primitives";
  result.reason = describeHit("embree", reference) + ", " + describeHit("obvh", candidate) + ": " + why;

  // The answers differ. obvh's answer stands when (1) its hit is real or borderline in double
  // precision, with matching values, and (2) nothing it did not report is a clear, nearer hit.
  double obvhT = std::numeric_limits<double>::infinity();
  if (candidate.hit()) {
    const double edgeTolerance = edgeToleranceFor(scene, ray, candidate.geomID, candidate.primID, tol);
    bool confirmed = false;
    for (const ExactPart& part : intersectExact(scene, ray, candidate.geomID, candidate.primID)) {
      const PartJudgement j = judge(part, ray, edgeTolerance, tol);
      HitRecord exact = candidate;
      exact.t = float(part.t), exact.u = float(part.u), exact.v = float(part.v);
      const double tSlack = distanceSlack(part, ray, edgeTolerance);
      const double uvSlack = part.minHeight > 0.0 ? edgeTolerance / (part.minHeight * std::max(part.cosine, 1e-6)) : 0.0;
      std::string ignored;
      if ((j.clearHit || j.borderline) && sameValues(exact, candidate, tol, ignored, tSlack, uvSlack)) confirmed = true;
    }
    if (!confirmed) {
      result.verdict = Verdict::Mismatch;
      result.reason += " (obvh's hit is not confirmed in double precision)";
      return result;
    }
    obvhT = candidate.t;
  }
  if (reference.hit()) {
    const double edgeTolerance = edgeToleranceFor(scene, ray, reference.geomID, reference.primID, tol);
    for (const ExactPart& part : intersectExact(scene, ray, reference.geomID, reference.primID)) {
      const PartJudgement j = judge(part, ray, edgeTolerance, tol);
      const double margin = std::max(tol.tRelative * std::fabs(part.t), distanceSlack(part, ray, edgeTolerance));
      if (j.clearHit && part.t < obvhT - margin) {
        result.verdict = Verdict::Mismatch;
        result.reason += " (obvh missed a clear, nearer hit)";
        return result;
      }
    }
  }
  result.verdict = Verdict::Ambiguous;
  return result;
}

OcclusionTruth exactOcclusion(const SceneData& scene, const RTCRay& ray, const CompareTolerance& tol) {
  bool ambiguous = false;
  for (unsigned geomID = 0; geomID < scene.meshes.size(); ++geomID) {
    const MeshData& mesh = scene.meshes[geomID];
    if (!mesh.enabled || (mesh.mask & ray.mask) == 0) continue;
    for (unsigned primID = 0; primID < mesh.primitiveCount(); ++primID) {
      const double edgeTolerance = edgeToleranceFor(scene, ray, geomID, primID, tol);
      for (const ExactPart& part : intersectExact(scene, ray, geomID, primID)) {
        const PartJudgement j = judge(part, ray, edgeTolerance, tol);
        if (j.clearHit) return OcclusionTruth::Occluded;
        if (j.borderline) ambiguous = true;
      }
    }
  }
  return ambiguous ? OcclusionTruth::Ambiguous : OcclusionTruth::Free;
}

Comparison judgeOcclusion(OcclusionTruth truth, bool referenceOccluded, bool candidateOccluded) {
  Comparison c;
  if (referenceOccluded == candidateOccluded) return c;
  const bool candidateRight = (truth == OcclusionTruth::Occluded) == candidateOccluded;
  c.verdict = truth == OcclusionTruth::Ambiguous || candidateRight ? Verdict::Ambiguous : Verdict::Mismatch;
  const char* truthName = truth == OcclusionTruth::Ambiguous  ? "borderline"
                          : truth == OcclusionTruth::Occluded ? "occluded"
                                                              : "free";
  c.reason = std::string("occlusion: reference ") + (referenceOccluded ? "occluded" : "free") + ", candidate " +
             (candidateOccluded ? "occluded" : "free") + ", double precision " + truthName;
  return c;
}

Comparison compareOcclusion(const SceneData& scene, const RTCRay& ray, bool referenceOccluded, bool candidateOccluded,
                            const CompareTolerance& tol) {
  if (referenceOccluded == candidateOccluded) return {};
  return judgeOcclusion(exactOcclusion(scene, ray, tol), referenceOccluded, candidateOccluded);
}

bool hitIsPlausible(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID,
                    const CompareTolerance& tol) {
  const double edgeTolerance = edgeToleranceFor(scene, ray, geomID, primID, tol);
  for (const ExactPart& part : intersectExact(scene, ray, geomID, primID)) {
    const PartJudgement j = judge(part, ray, edgeTolerance, tol);
    if (j.clearHit || j.borderline) return true;
  }
  return false;
}

std::string describeRay(const RTCRay& r) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tnear=%a tfar=%a mask=0x%x", r.org_x, r.org_y,
                r.org_z, r.dir_x, r.dir_y, r.dir_z, r.tnear, r.tfar, r.mask);
  return buf;
}

std::string describePrimitive(const SceneData& scene, unsigned geomID, unsigned primID) {
  const MeshData& mesh = scene.meshes.at(geomID);
  char buf[128];
  std::snprintf(buf, sizeof buf, "geom %u prim %u:", geomID, primID);
  std::string out = buf;
  if (mesh.grid) {  // a grid's corners (its cells can be many)
    const RTCGrid& g = mesh.grids.at(primID);
    std::snprintf(buf, sizeof buf, " grid start %u stride %u, %u x %u vertices", g.startVertexID, g.stride, g.width,
                  g.height);
    return out + buf;
  }
  const int corners = mesh.quads ? 4 : 3;
  for (int c = 0; c < corners; ++c) {
    const float* v = &mesh.vertices[3 * size_t(mesh.indices[size_t(primID) * corners + c])];
    std::snprintf(buf, sizeof buf, " (%a, %a, %a)", v[0], v[1], v[2]);
    out += buf;
  }
  return out;
}

}  // namespace obvh::tools
