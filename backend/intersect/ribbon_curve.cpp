#include "intersect/ribbon_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace obvh {
namespace {

struct Vec3d {
  double x, y, z;
};
Vec3d operator+(const Vec3d& a, const Vec3d& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3d operator-(const Vec3d& a, const Vec3d& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3d operator*(double s, const Vec3d& a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(const Vec3d& a, const Vec3d& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3d cross(const Vec3d& a, const Vec3d& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double largestComponent(const Vec3d& a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }

// The curve's point, radius and tangent at u (double, in the segment's own basis).
struct RibbonPoint {
  Vec3d p, tangent;
  double r;
};

RibbonPoint evaluate(const double w[4], const double dw[4], const ShapeVertex control[4]) {
  RibbonPoint e{{0, 0, 0}, {0, 0, 0}, 0.0};
  for (int k = 0; k < 4; ++k) {
    const Vec3d c{control[k].p.x, control[k].p.y, control[k].p.z};
    e.p = e.p + w[k] * c;
    e.tangent = e.tangent + dw[k] * c;
    e.r += w[k] * double(control[k].r);
  }
  return e;
}

// Every basis' weights and their derivatives at u = i / N, for every N a segment can be cut into.
struct QuadEndWeights {
  double w[17][4], dw[17][4];
};
const QuadEndWeights& quadEndWeights(CurveBasis basis, int quads) {
  static const auto table = [] {
    auto t = std::make_unique<QuadEndWeights[]>(3 * 17);
    for (int b = 0; b < 3; ++b)
      for (int n = 1; n <= 16; ++n)
        for (int i = 0; i <= n; ++i) {
          const CurveBasisWeights weights = curveBasisWeights(CurveBasis(b), double(i) / double(n));
          std::copy(weights.w, weights.w + 4, t[b * 17 + n].w[i]);
          std::copy(weights.dw, weights.dw + 4, t[b * 17 + n].dw[i]);
        }
    return t;
  }();
  return table[int(basis) * 17 + quads];
}

// The distance, across the ray, between the ray and the segment from a to b (rays that pass
// farther from a quad's chord than both its radii cannot meet the quad).
double distanceAcross(const Vec3d& org, const Vec3d& unitDir, const Vec3d& a, const Vec3d& b) {
  const auto across = [&](const Vec3d& p) {
    const Vec3d q = p - org;
    return q - dot(q, unitDir) * unitDir;
  };
  const Vec3d qa = across(a), qab = across(b) - qa;
  const double length2 = dot(qab, qab);
  const double s = length2 > 0.0 ? std::clamp(-dot(qa, qab) / length2, 0.0, 1.0) : 0.0;
  const Vec3d nearest = qa + s * qab;
  return std::sqrt(dot(nearest, nearest));
}

// One-sided ray/triangle test (the side Embree's ribbon quads face the ray with); barycentric b
// weighs corner b, c weighs corner c.
bool hitTriangle(const Vec3d& org, const Vec3d& dir, const Vec3d& a, const Vec3d& b, const Vec3d& c, double& t,
                 double& wb, double& wc) {
  const Vec3d e1 = b - a, e2 = c - a, p = cross(dir, e2);
  const double det = dot(e1, p);
  if (!(det < 0.0)) return false;
  const Vec3d s = org - a, q = cross(s, e1);
  wb = dot(s, p) / det;
  wc = dot(dir, q) / det;
  t = dot(e2, q) / det;
  return wb >= 0.0 && wc >= 0.0 && wb + wc <= 1.0;
}

}  // namespace

int ribbonQuadCount(float tessellationRate) {
  if (!(tessellationRate >= 1.f)) return 1;
  return tessellationRate >= 16.f ? 16 : int(tessellationRate);
}

Box3f ribbonCurveBounds(CurveBasis basis, const ShapeVertex control[4]) {
  const CubicBezier bezier = bezierOf(basis, control);
  float radius = 0.f, magnitude = 0.f;
  for (const ShapeVertex& c : bezier.p) {
    radius = std::max(radius, std::fabs(c.r));
    magnitude = std::max({magnitude, std::fabs(c.p.x), std::fabs(c.p.y), std::fabs(c.p.z)});
  }
  // The Bezier form was rounded to float; the quads come from the exact curve.
  const float pad = radius * (1.f + 1e-6f) + magnitude * 4.f * std::numeric_limits<float>::epsilon();
  Box3f box;
  for (const ShapeVertex& c : bezier.p) {
    box.extend(c.p - Vec3f{pad, pad, pad});
    box.extend(c.p + Vec3f{pad, pad, pad});
  }
  return box;
}

bool intersectRibbonCurve(const Ray& ray, CurveBasis basis, const ShapeVertex control[4], int quads, ShapeHit& hit) {
  const Vec3d org{ray.org.x, ray.org.y, ray.org.z}, dir{ray.dir.x, ray.dir.y, ray.dir.z};
  const double length = std::sqrt(dot(dir, dir));
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  const Vec3d unitDir = (1.0 / length) * dir;
  // Embree takes the chord for a tangent that vanishes within rounding of the control points.
  double magnitude = 0.0;
  for (int k = 0; k < 4; ++k)
    magnitude = std::max(magnitude, largestComponent(Vec3d{control[k].p.x, control[k].p.y, control[k].p.z} - org));
  const double vanishing = 4.0 * double(std::numeric_limits<float>::epsilon()) * magnitude;

  quads = std::clamp(quads, 1, 16);
  const QuadEndWeights& weights = quadEndWeights(basis, quads);
  RibbonPoint points[17];
  for (int i = 0; i <= quads; ++i) points[i] = evaluate(weights.w[i], weights.dw[i], control);

  bool found = false;
  double bestT = std::numeric_limits<double>::infinity(), bestAlong = 0.0, bestAcross = 0.0;
  int bestQuad = 0;
  for (int i = 0; i < quads; ++i) {
    const RibbonPoint &start = points[i], &end = points[i + 1];
    const double reach = std::max(std::fabs(start.r), std::fabs(end.r));
    if (distanceAcross(org, unitDir, start.p, end.p) > reach * (1.0 + 1e-9) + 1e-12 * magnitude) continue;
    const Vec3d chord = end.p - start.p;
    const auto acrossAt = [&](const RibbonPoint& e, Vec3d& n) {
      const Vec3d tangent = largestComponent(e.tangent) < vanishing ? chord : e.tangent;
      n = cross(tangent, unitDir);
      const double l = std::sqrt(dot(n, n));
      if (!(l > 0.0)) return false;
      n = (1.0 / l) * n;
      return true;
    };
    Vec3d n0, n1;
    if (!acrossAt(start, n0) || !acrossAt(end, n1)) continue;
    const Vec3d corner[4] = {start.p + start.r * n0, end.p + end.r * n1, end.p - end.r * n1, start.p - start.r * n0};
    for (int half = 0; half < 2; ++half) {
      double t, wb, wc;
      const bool inside = half == 0 ? hitTriangle(org, dir, corner[0], corner[1], corner[3], t, wb, wc)
                                    : hitTriangle(org, dir, corner[2], corner[3], corner[1], t, wb, wc);
      if (!inside || !(t >= double(ray.tnear) && t <= double(ray.tfar)) || !(t < bestT)) continue;
      // The second triangle runs the quad's coordinates backwards from its far corner.
      const double along = half == 0 ? wb : 1.0 - wb, across = half == 0 ? wc : 1.0 - wc;
      const double radius = start.r + along * (end.r - start.r);
      if (!(t * length > 2.0 * radius)) continue;
      found = true;
      bestT = t, bestAlong = along, bestAcross = across, bestQuad = i;
    }
  }
  if (!found) return false;
  const double u = (double(bestQuad) + bestAlong) / double(quads);
  const CurveBasisWeights at = curveBasisWeights(basis, u);
  const Vec3d tangent = evaluate(at.w, at.dw, control).tangent;
  hit.t = float(bestT);
  hit.u = float(u);
  hit.v = float(2.0 * bestAcross - 1.0);
  hit.Ng = {float(tangent.x), float(tangent.y), float(tangent.z)};
  return true;
}

}  // namespace obvh
