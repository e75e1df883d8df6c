#include "intersect/round_curve.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace obvh {
namespace {

// A control point in the ray's frame (x, y across the ray, z along it) with its radius.
struct Control {
  double x[3];
  double r;
};

using Controls = Control[4];

struct CurvePoint {
  double p[3], r;      // position and radius
  double dp[3], dr;    // first derivatives in u
  double ddp[3];       // second derivative of the position
};

CurvePoint evaluate(const Controls& c, double u) {
  const double s = 1.0 - u;
  const double b[4] = {s * s * s, 3.0 * s * s * u, 3.0 * s * u * u, u * u * u};
  const double db[3] = {3.0 * s * s, 6.0 * s * u, 3.0 * u * u};  // weights of the differences
  const double ddb[2] = {6.0 * s, 6.0 * u};                        // weights of the second differences
  CurvePoint e{};
  for (int k = 0; k < 4; ++k) {
    for (int a = 0; a < 3; ++a) e.p[a] += b[k] * c[k].x[a];
    e.r += b[k] * c[k].r;
  }
  for (int k = 0; k < 3; ++k) {
    for (int a = 0; a < 3; ++a) e.dp[a] += db[k] * (c[k + 1].x[a] - c[k].x[a]);
    e.dr += db[k] * (c[k + 1].r - c[k].r);
  }
  for (int k = 0; k < 2; ++k)
    for (int a = 0; a < 3; ++a) e.ddp[a] += ddb[k] * (c[k + 2].x[a] - 2.0 * c[k + 1].x[a] + c[k].x[a]);
  return e;
}

double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// de Casteljau at the middle.
void halve(const Controls& c, Controls& left, Controls& right) {
  const auto mid = [](const Control& a, const Control& b) {
    Control m;
    for (int k = 0; k < 3; ++k) m.x[k] = 0.5 * (a.x[k] + b.x[k]);
    m.r = 0.5 * (a.r + b.r);
    return m;
  };
  const Control ab = mid(c[0], c[1]), bc = mid(c[1], c[2]), cd = mid(c[2], c[3]);
  const Control abc = mid(ab, bc), bcd = mid(bc, cd), centre = mid(abc, bcd);
  left[0] = c[0], left[1] = ab, left[2] = abc, left[3] = centre;
  right[0] = centre, right[1] = bcd, right[2] = cd, right[3] = c[3];
}

struct Solver {
  const Controls& curve;  // the whole segment, u in [0, 1]
  double sNear, sFar;     // the ray's segment, in distance along its unit direction
  double scale;           // the size of the problem, for tolerances
  double bestS = std::numeric_limits<double>::infinity();
  double bestU = 0.0;

  // A piece [u0, u1] of the segment with its end points, which every ray point is compared with.
  struct Piece {
    double u0, u1;
    CurvePoint start, end;
  };

  // How far the ray's point X = (0, 0, s) lies outside the piece of the tube: |X - p| - r at the
  // piece's point nearest to X, where the slope of the squared distance, -(X - p) . p', changes
  // sign (found by Newton's method kept inside a shrinking bracket, from u, updated). When the
  // slope does not change sign, X lies beyond the plane of an end circle, outside the piece
  // (beyond the tube's open end, or in the next piece's stretch): then its distance to that plane
  // counts, so that no end cap appears.
  double outside(double s, const Piece& piece, double& u) const {
    const auto slopeAt = [&](const CurvePoint& e) {
      return e.p[0] * e.dp[0] + e.p[1] * e.dp[1] - (s - e.p[2]) * e.dp[2];
    };
    const auto distanceTo = [&](const CurvePoint& e) {
      return std::sqrt(e.p[0] * e.p[0] + e.p[1] * e.p[1] + (s - e.p[2]) * (s - e.p[2])) - e.r;
    };
    const auto beyondEnd = [&](const CurvePoint& e, double slope) {
      const double speed = std::sqrt(dot3(e.dp, e.dp));
      return std::max(distanceTo(e), speed > 0.0 ? std::fabs(slope) / speed : 0.0);
    };
    const double startSlope = slopeAt(piece.start);
    if (startSlope >= 0.0) {
      u = piece.u0;
      return beyondEnd(piece.start, startSlope);
    }
    const double endSlope = slopeAt(piece.end);
    if (endSlope <= 0.0) {
      u = piece.u1;
      return beyondEnd(piece.end, endSlope);
    }
    double lo = piece.u0, hi = piece.u1;
    u = std::clamp(u, lo, hi);
    CurvePoint e = evaluate(curve, u);
    for (int iteration = 0; iteration < 64 && hi - lo > 1e-7 * (piece.u1 - piece.u0); ++iteration) {
      const double slope = slopeAt(e);
      if (slope == 0.0) break;
      (slope < 0.0 ? lo : hi) = u;
      const double w[3] = {-e.p[0], -e.p[1], s - e.p[2]};
      const double curvature = dot3(e.dp, e.dp) - dot3(w, e.ddp);
      const double newton = curvature > 0.0 ? u - slope / curvature : lo - 1.0;
      const double next = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
      const bool done = std::fabs(next - u) <= 1e-7 * (piece.u1 - piece.u0);
      u = next;
      e = evaluate(curve, u);
      if (done) break;
    }
    return distanceTo(e);
  }

  // Polishes a root bracketed closely with Newton's method on both conditions,
  // F1 = (X - p) . p' = 0 (X lies in the plane of the circle at u) and F2 = |X - p|^2 - r^2 = 0,
  // and keeps it if it is a root.
  void polish(double u, double s, double radius) {
    for (int iteration = 0; iteration < 8; ++iteration) {
      const CurvePoint e = evaluate(curve, u);
      const double w[3] = {-e.p[0], -e.p[1], s - e.p[2]};
      const double f1 = dot3(w, e.dp), f2 = dot3(w, w) - e.r * e.r;
      const double j11 = -dot3(e.dp, e.dp) + dot3(w, e.ddp), j12 = e.dp[2];
      const double j21 = -2.0 * f1 - 2.0 * e.r * e.dr, j22 = 2.0 * w[2];
      const double det = j11 * j22 - j12 * j21;
      if (!(std::fabs(det) > 0.0) || !std::isfinite(det)) break;
      const double du = (f1 * j22 - f2 * j12) / det, ds = (j11 * f2 - j21 * f1) / det;
      if (std::fabs(du) > 1e-3 || std::fabs(ds) > 1e-4 * radius) break;  // a polish, not a search
      u -= du, s -= ds;
      if (std::fabs(du) <= 1e-15 && std::fabs(ds) <= 1e-15 * scale) break;
    }
    accept(u, s);
  }

  void accept(double u, double s) {
    if (u < 0.0 || u > 1.0 || !(s >= sNear && s <= sFar) || !(s < bestS)) return;
    const CurvePoint e = evaluate(curve, u);
    if (!(e.r > 0.0)) return;
    const double w[3] = {-e.p[0], -e.p[1], s - e.p[2]};
    const double tangent = std::sqrt(dot3(e.dp, e.dp));
    // On the circle at u: a point whose nearest curve point is a piece's end (beyond the open end
    // of the tube, or in the next piece's stretch) is not.
    if (std::fabs(std::sqrt(dot3(w, w)) - e.r) > 1e-7 * scale || std::fabs(dot3(w, e.dp)) > 1e-7 * scale * tangent)
      return;
    bestS = s, bestU = u;
  }

  // The ray's hits on the tube around the piece [u0, u1], short and nearly straight: along the ray,
  // how far outside the tube the ray's point lies falls and rises once; where it is least is
  // found by golden-section search, and the crossings before and after it by regula falsi, close
  // enough for Newton's method to finish them. That distance changes by at most `lipschitz` per
  // unit along the ray (1, plus the radius' slope), which ends the search for rays that pass by.
  void solvePiece(double u0, double u1, double depthLow, double depthHigh, double radius, double lipschitz) {
    const double low = std::max(sNear, depthLow), high = std::min({sFar, bestS, depthHigh});
    if (!(low <= high)) return;
    const Piece piece{u0, u1, evaluate(curve, u0), evaluate(curve, u1)};
    double u = 0.5 * (u0 + u1);
    constexpr double kGolden = 0.6180339887498949;
    double a = low, b = high;
    double c = b - kGolden * (b - a), d = a + kGolden * (b - a);
    double uc = u, ud = u;
    double fc = outside(c, piece, uc), fd = outside(d, piece, ud);
    for (int iteration = 0; iteration < 64 && b - a > 1e-9 * scale; ++iteration) {
      if (fc < 0.0 || fd < 0.0) break;                      // inside somewhere: that bounds both crossings
      if (std::min(fc, fd) > lipschitz * (b - a)) return;  // outside all along
      if (fc <= fd) {
        b = d, d = c, fd = fc, ud = uc;
        c = b - kGolden * (b - a);
        uc = ud;
        fc = outside(c, piece, uc);
      } else {
        a = c, c = d, fc = fd, uc = ud;
        d = a + kGolden * (b - a);
        ud = uc;
        fd = outside(d, piece, ud);
      }
    }
    const double inside = fc <= fd ? c : d;
    double uInside = fc <= fd ? uc : ud;
    if (std::min(fc, fd) > 0.0) return;
    // Crossings: from low (outside, unless the ray starts inside) to inside, and from inside to high.
    const auto crossing = [&](double from, double to) {
      double uOut = uInside;
      double fOut = outside(from, piece, uOut);
      if (!(fOut > 0.0)) return;
      // Regula falsi, Illinois variant: the distance is smooth across the wall.
      double out = from, in = to, uIn = uInside, fIn = std::min(fc, fd);
      int side = 0;
      for (int iteration = 0; iteration < 64 && std::fabs(in - out) > 1e-6 * radius; ++iteration) {
        double next = out - fOut * (in - out) / (fIn - fOut);
        if (!(next != out && next != in && (next - out) * (next - in) < 0.0)) next = 0.5 * (out + in);
        double uNext = uIn;
        const double f = outside(next, piece, uNext);
        if (f > 0.0) {
          out = next, fOut = f;
          if (side == 1) fIn *= 0.5;
          side = 1;
        } else {
          in = next, fIn = f, uIn = uNext;
          if (side == -1) fOut *= 0.5;
          side = -1;
        }
      }
      polish(uIn, in, radius);
    };
    crossing(low, inside);
    crossing(high, inside);
  }

  // Whether the ray (the z axis) passes farther than radius from the piece's control points'
  // convex hull, seen along the ray: that hull lies within the largest distance of the inner
  // control points from the chord of the chord itself.
  static bool passesBeside(const Controls& piece, double radius) {
    const auto distanceToChord = [&](double x, double y) {
      const double cx = piece[3].x[0] - piece[0].x[0], cy = piece[3].x[1] - piece[0].x[1];
      const double ox = x - piece[0].x[0], oy = y - piece[0].x[1];
      const double cc = cx * cx + cy * cy;
      const double f = cc > 0.0 ? std::clamp((ox * cx + oy * cy) / cc, 0.0, 1.0) : 0.0;
      return std::hypot(ox - f * cx, oy - f * cy);
    };
    const double spread = std::max(distanceToChord(piece[1].x[0], piece[1].x[1]),
                                   distanceToChord(piece[2].x[0], piece[2].x[1]));
    return distanceToChord(0.0, 0.0) > radius + spread;
  }

  // Halves the piece while the ray can meet its bounds; small enough pieces are solved.
  void search(const Controls& piece, double u0, double u1, int depth) {
    double lower[3], upper[3], radius = 0.0;
    for (int k = 0; k < 3; ++k) lower[k] = upper[k] = piece[0].x[k];
    for (const Control& c : piece) {
      for (int k = 0; k < 3; ++k) lower[k] = std::min(lower[k], c.x[k]), upper[k] = std::max(upper[k], c.x[k]);
      radius = std::max(radius, std::fabs(c.r));
    }
    if (lower[0] > radius || upper[0] < -radius || lower[1] > radius || upper[1] < -radius) return;
    if (lower[2] - radius > std::min(sFar, bestS) || upper[2] + radius < sNear) return;
    if (passesBeside(piece, radius)) return;
    // Flat enough for the cylinder's starting points: the inner control points lie close to the chord.
    double bend = 0.0;
    const double chord[3] = {piece[3].x[0] - piece[0].x[0], piece[3].x[1] - piece[0].x[1], piece[3].x[2] - piece[0].x[2]};
    const double cc = dot3(chord, chord);
    for (int i = 1; i <= 2; ++i) {
      double off[3] = {piece[i].x[0] - piece[0].x[0], piece[i].x[1] - piece[0].x[1], piece[i].x[2] - piece[0].x[2]};
      const double f = cc > 0.0 ? dot3(off, chord) / cc : 0.0;
      for (int k = 0; k < 3; ++k) off[k] -= f * chord[k];
      bend = std::max(bend, std::sqrt(dot3(off, off)));
    }
    // And short: within a piece no longer than its radius the tube has at most the two walls a
    // cylinder has, even where it bends tighter than its radius and overlaps itself.
    const bool small = bend <= 0.125 * radius && cc <= radius * radius;
    if (depth >= 12 || (depth >= 2 && small)) {
      double radiusStep = 0.0;
      for (int i = 0; i < 3; ++i) radiusStep = std::max(radiusStep, std::fabs(piece[i + 1].r - piece[i].r));
      // The radius changes by at most 3 radiusStep over the piece, about a chord long (doubled, to be safe).
      const double lipschitz = cc > 0.0 ? 1.0 + 6.0 * radiusStep / std::sqrt(cc) : 1e300;
      return solvePiece(u0, u1, lower[2] - radius, upper[2] + radius, radius, lipschitz);
    }
    Controls left, right;
    halve(piece, left, right);
    const double mid = 0.5 * (u0 + u1);
    search(left, u0, mid, depth + 1);
    search(right, mid, u1, depth + 1);
  }
};

}  // namespace

Box3f roundCurveBounds(const CubicBezier& curve) {
  float radius = 0.f;
  for (const ShapeVertex& c : curve.p) radius = std::max(radius, std::fabs(c.r));
  Box3f box;
  for (const ShapeVertex& c : curve.p) {
    box.extend(c.p - Vec3f{radius, radius, radius});
    box.extend(c.p + Vec3f{radius, radius, radius});
  }
  return box;
}

bool intersectRoundCurve(const Ray& ray, const CubicBezier& curve, ShapeHit& hit) {
  const double d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  const double length = std::sqrt(dot3(d, d));
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  // An orthonormal frame whose z axis is the ray's direction.
  const double z[3] = {d[0] / length, d[1] / length, d[2] / length};
  const double helper[3] = {std::fabs(z[0]) < 0.9 ? 1.0 : 0.0, std::fabs(z[0]) < 0.9 ? 0.0 : 1.0, 0.0};
  double x[3] = {helper[1] * z[2] - helper[2] * z[1], helper[2] * z[0] - helper[0] * z[2],
                 helper[0] * z[1] - helper[1] * z[0]};
  const double xl = std::sqrt(dot3(x, x));
  for (double& c : x) c /= xl;
  const double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};

  Controls controls;
  double scale = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double q[3] = {double(curve.p[k].p.x) - ray.org.x, double(curve.p[k].p.y) - ray.org.y,
                         double(curve.p[k].p.z) - ray.org.z};
    controls[k] = {{dot3(q, x), dot3(q, y), dot3(q, z)}, double(curve.p[k].r)};
    for (double c : controls[k].x) scale = std::max(scale, std::fabs(c));
    scale = std::max(scale, std::fabs(controls[k].r));
  }
  if (!std::isfinite(scale)) return false;
  Solver solver{controls, double(ray.tnear) * length, double(ray.tfar) * length, std::max(scale, 1e-30)};
  solver.search(controls, 0.0, 1.0, 0);
  if (!std::isfinite(solver.bestS)) return false;
  const double t = solver.bestS / length;
  if (!(float(t) >= ray.tnear && float(t) <= ray.tfar)) return false;
  const CurvePoint e = evaluate(controls, solver.bestU);
  const double w[3] = {-e.p[0], -e.p[1], solver.bestS - e.p[2]};
  const double tangent2 = dot3(e.dp, e.dp);
  double n[3];
  for (int k = 0; k < 3; ++k) n[k] = tangent2 * w[k] / e.r - e.dr * e.dp[k];
  hit.t = float(t);
  hit.u = float(solver.bestU);
  hit.Ng = {float(n[0] * x[0] + n[1] * y[0] + n[2] * z[0]), float(n[0] * x[1] + n[1] * y[1] + n[2] * z[1]),
            float(n[0] * x[2] + n[1] * y[2] + n[2] * z[2])};
  return true;
}

}  // namespace obvh
