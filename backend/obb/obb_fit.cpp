#include <array>
#include <cmath>
#include <limits>

#include "obb/obb.h"

namespace obvh {
namespace {

Vec3f normalized(Vec3f v) {
  const float length = std::sqrt(dot(v, v));
  return length > 0.f ? v * (1.f / length) : Vec3f{0.f, 0.f, 0.f};
}

float lengthSquared(Vec3f v) { return dot(v, v); }

// Surface area proxy of the box with these axes over a small point set (no rounding outwards).
float halfAreaAlong(const Vec3f axes[3], const Vec3f* points, size_t count) {
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = dot(axes[k], points[0]);
  for (size_t i = 1; i < count; ++i)
    for (int k = 0; k < 3; ++k) {
      const float d = dot(axes[k], points[i]);
      lo[k] = std::min(lo[k], d);
      hi[k] = std::max(hi[k], d);
    }
  const float a = hi[0] - lo[0], b = hi[1] - lo[1], c = hi[2] - lo[2];
  return a * b + b * c + c * a;
}

// Tries the three frames (edge, normal, edge x normal) of triangle (a, b, c).
void tryTriangle(Vec3f a, Vec3f b, Vec3f c, const Vec3f* extremal, size_t count, Vec3f best[3], float& bestArea) {
  const Vec3f n = normalized(cross(b - a, c - a));
  if (lengthSquared(n) == 0.f) return;
  for (const Vec3f& edge : {b - a, c - b, a - c}) {
    const Vec3f e = normalized(edge);
    if (lengthSquared(e) == 0.f) continue;
    const Vec3f axes[3] = {e, n, normalized(cross(e, n))};
    const float area = halfAreaAlong(axes, extremal, count);
    if (area < bestArea) {
      bestArea = area;
      for (int k = 0; k < 3; ++k) best[k] = axes[k];
    }
  }
}

// Symmetric 3x3 eigenvectors by cyclic Jacobi rotations.
std::array<Vec3f, 3> eigenvectors(double m[3][3]) {
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::fabs(m[p][q]) < 1e-300) continue;
        const double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // m = J^T m J
          const double mkp = m[k][p], mkq = m[k][q];
          m[k][p] = c * mkp - s * mkq;
          m[k][q] = s * mkp + c * mkq;
        }
        for (int k = 0; k < 3; ++k) {
          const double mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::array<Vec3f, 3> out;
  for (int k = 0; k < 3; ++k) out[k] = normalized({float(v[0][k]), float(v[1][k]), float(v[2][k])});
  return out;
}

// Makes three nearly orthonormal float axes exactly as orthogonal as float allows (Gram-Schmidt).
void orthonormalize(Vec3f axes[3]) {
  axes[0] = normalized(axes[0]);
  axes[1] = normalized(axes[1] - axes[0] * dot(axes[0], axes[1]));
  axes[2] = normalized(cross(axes[0], axes[1]));
}

}  // namespace

bool Obb::contains(Vec3f p, float slack) const {
  const Vec3f q = toBoxFrame(p);
  for (int k = 0; k < 3; ++k)
    if (q[k] < lower[k] - slack || q[k] > upper[k] + slack) return false;
  return true;
}

Obb fitWithAxes(const Vec3f axes[3], const Vec3f* points, size_t count) {
  Obb box;
  for (int k = 0; k < 3; ++k) box.axis[k] = axes[k];
  if (count == 0) return box;
  // Projections in double, rounded outwards: every float point is inside the float box as
  // long as the query side (Obb::toBoxFrame in float) allows for its own rounding.
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<double>::infinity(), hi[k] = -lo[k];
  for (size_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) {
      const double d = double(axes[k].x) * points[i].x + double(axes[k].y) * points[i].y + double(axes[k].z) * points[i].z;
      lo[k] = std::min(lo[k], d);
      hi[k] = std::max(hi[k], d);
    }
  for (int k = 0; k < 3; ++k) {
    float l = float(lo[k]), h = float(hi[k]);
    if (double(l) > lo[k]) l = std::nextafter(l, -std::numeric_limits<float>::infinity());
    if (double(h) < hi[k]) h = std::nextafter(h, std::numeric_limits<float>::infinity());
    box.lower[k] = l, box.upper[k] = h;
  }
  return box;
}

Obb fitAxisAligned(const Vec3f* points, size_t count) {
  const Vec3f axes[3] = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}};
  return fitWithAxes(axes, points, count);
}

Obb fitDito14(const Vec3f* points, size_t count) {
  const Obb aligned = fitAxisAligned(points, count);
  if (count < 3) return aligned;
  static const Vec3f kNormals[7] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1}};
  Vec3f extremal[14];
  float lo[7], hi[7];
  for (int k = 0; k < 7; ++k) {
    lo[k] = hi[k] = dot(kNormals[k], points[0]);
    extremal[2 * k] = extremal[2 * k + 1] = points[0];
  }
  for (size_t i = 1; i < count; ++i)
    for (int k = 0; k < 7; ++k) {
      const float d = dot(kNormals[k], points[i]);
      if (d < lo[k]) lo[k] = d, extremal[2 * k] = points[i];
      if (d > hi[k]) hi[k] = d, extremal[2 * k + 1] = points[i];
    }
  // Base triangle: the farthest extremal pair, then the extremal point farthest from that line.
  int pair = 0;
  float farthest = -1.f;
  for (int k = 0; k < 7; ++k) {
    const float d = lengthSquared(extremal[2 * k + 1] - extremal[2 * k]);
    if (d > farthest) farthest = d, pair = k;
  }
  const Vec3f p0 = extremal[2 * pair], p1 = extremal[2 * pair + 1];
  const Vec3f e0 = normalized(p1 - p0);
  Vec3f p2 = p0;
  float lineDistance = -1.f;
  for (const Vec3f& q : extremal) {
    const Vec3f v = q - p0;
    const float d = lengthSquared(v - e0 * dot(v, e0));
    if (d > lineDistance) lineDistance = d, p2 = q;
  }
  Vec3f best[3] = {aligned.axis[0], aligned.axis[1], aligned.axis[2]};
  float bestArea = halfAreaAlong(best, extremal, 14);
  if (lineDistance > 0.f) {
    tryTriangle(p0, p1, p2, extremal, 14, best, bestArea);
    // The ditetrahedron: the extremal points farthest above and below the base triangle.
    const Vec3f n = normalized(cross(p1 - p0, p2 - p0));
    Vec3f above = p0, below = p0;
    float maxD = 0.f, minD = 0.f;
    for (const Vec3f& q : extremal) {
      const float d = dot(n, q - p0);
      if (d > maxD) maxD = d, above = q;
      if (d < minD) minD = d, below = q;
    }
    for (const Vec3f& apex : {above, below}) {
      if (lengthSquared(apex - p0) == 0.f) continue;
      tryTriangle(p0, p1, apex, extremal, 14, best, bestArea);
      tryTriangle(p1, p2, apex, extremal, 14, best, bestArea);
      tryTriangle(p2, p0, apex, extremal, 14, best, bestArea);
    }
  }
  orthonormalize(best);
  const Obb fitted = fitWithAxes(best, points, count);
  return fitted.halfArea() < aligned.halfArea() ? fitted : aligned;
}

Obb fitPca(const Vec3f* points, size_t count) {
  if (count < 2) return fitAxisAligned(points, count);
  double mean[3] = {0, 0, 0};
  for (size_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) mean[k] += points[i][k];
  for (double& m : mean) m /= double(count);
  double c[3][3] = {};
  for (size_t i = 0; i < count; ++i)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) c[a][b] += (points[i][a] - mean[a]) * (points[i][b] - mean[b]);
  const std::array<Vec3f, 3> vectors = eigenvectors(c);
  Vec3f axes[3] = {vectors[0], vectors[1], vectors[2]};
  orthonormalize(axes);
  return fitWithAxes(axes, points, count);
}

Obb fitObb(ObbFit method, const Vec3f* points, size_t count) {
  return method == ObbFit::Pca ? fitPca(points, count) : fitDito14(points, count);
}

}  // namespace obvh
