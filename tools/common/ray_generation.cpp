#include "ray_generation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "offset_ray.h"

namespace obvh::tools {
namespace {

RTCRay makeRay(const float org[3], const float dir[3]) {
  RTCRay r{};
  r.org_x = org[0];
  r.org_y = org[1];
  r.org_z = org[2];
  r.dir_x = dir[0];
  r.dir_y = dir[1];
  r.dir_z = dir[2];
  r.tnear = 0.f;
  r.tfar = std::numeric_limits<float>::infinity();
  r.mask = 0xFFFFFFFFu;
  return r;
}

void normalize(float v[3]) {
  const float l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; ++k) v[k] /= l;
}

void crossf(const float a[3], const float b[3], float out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

}  // namespace

std::vector<RTCRay> perspectiveRays(const SceneBox& box, int width, int height) {
  float center[3], extent = 0.f;
  for (int k = 0; k < 3; ++k) {
    center[k] = 0.5f * (box.lower[k] + box.upper[k]);
    extent = std::max(extent, box.upper[k] - box.lower[k]);
  }
  float forward[3] = {-0.35f, -0.3f, -1.f};
  normalize(forward);
  const float distance = 1.6f * extent;
  const float eye[3] = {center[0] - forward[0] * distance, center[1] - forward[1] * distance,
                        center[2] - forward[2] * distance};
  const float worldUp[3] = {0.f, 1.f, 0.f};
  float right[3], up[3];
  crossf(forward, worldUp, right);
  normalize(right);
  crossf(right, forward, up);
  const float tanHalfFov = std::tan(0.5f * 45.f * 3.14159265f / 180.f);
  const float aspect = float(width) / float(height);
  std::vector<RTCRay> rays;
  rays.reserve(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float px = (2.f * (x + 0.5f) / width - 1.f) * tanHalfFov * aspect;
      const float py = (1.f - 2.f * (y + 0.5f) / height) * tanHalfFov;
      float dir[3];
      for (int k = 0; k < 3; ++k) dir[k] = forward[k] + px * right[k] + py * up[k];
      normalize(dir);
      rays.push_back(makeRay(eye, dir));
    }
  return rays;
}

std::vector<RTCRay> orthographicRays(const SceneBox& box, int width, int height) {
  const float sx = box.upper[0] - box.lower[0], sy = box.upper[1] - box.lower[1];
  const float size = 1.05f * std::max(sx, sy * float(width) / float(height));
  const float cx = 0.5f * (box.lower[0] + box.upper[0]), cy = 0.5f * (box.lower[1] + box.upper[1]);
  const float z = box.upper[2] + 1.f + 0.1f * size;
  const float dir[3] = {0.f, 0.f, -1.f};
  const float pixel = size / float(width);
  std::vector<RTCRay> rays;
  rays.reserve(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float org[3] = {cx + (x + 0.5f - 0.5f * width) * pixel, cy + (0.5f * height - y - 0.5f) * pixel, z};
      rays.push_back(makeRay(org, dir));
    }
  return rays;
}

std::vector<RTCRay> randomRays(const SceneBox& box, size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  float center[3], extent = 0.f;
  for (int k = 0; k < 3; ++k) {
    center[k] = 0.5f * (box.lower[k] + box.upper[k]);
    extent = std::max(extent, box.upper[k] - box.lower[k]);
  }
  std::vector<RTCRay> rays;
  rays.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    float org[3], target[3], dir[3];
    for (int k = 0; k < 3; ++k) {
      org[k] = center[k] + (unit(rng) - 0.5f) * 2.f * extent;
      target[k] = box.lower[k] + unit(rng) * (box.upper[k] - box.lower[k]);
      dir[k] = target[k] - org[k];
    }
    if (dir[0] == 0.f && dir[1] == 0.f && dir[2] == 0.f) dir[2] = 1.f;
    rays.push_back(makeRay(org, dir));
  }
  return rays;
}

std::vector<RTCRay> pointSourceRays(const float source[3], size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal;
  std::vector<RTCRay> rays;
  rays.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    float dir[3] = {normal(rng), normal(rng), normal(rng)};
    if (dir[0] == 0.f && dir[1] == 0.f && dir[2] == 0.f) dir[2] = 1.f;
    rays.push_back(makeRay(source, dir));
  }
  return rays;
}

std::vector<RTCRay> shadowRaysTowardsSceneLight(const std::vector<RTCRay>& primary,
                                                const std::vector<RTCRayHit>& hits, const SceneBox& box) {
  std::vector<float> hitT(hits.size());
  for (size_t i = 0; i < hits.size(); ++i)
    hitT[i] = hits[i].hit.geomID != RTC_INVALID_GEOMETRY_ID ? hits[i].ray.tfar : std::numeric_limits<float>::infinity();
  const float extent = std::max({box.upper[0] - box.lower[0], box.upper[1] - box.lower[1], box.upper[2] - box.lower[2]});
  const float light[3] = {box.upper[0] + extent, box.upper[1] + 2.f * extent, box.upper[2] + extent};
  return shadowRays(primary, hitT, light);
}

std::vector<RTCRay> shadowRays(const std::vector<RTCRay>& primary, const std::vector<float>& hitT,
                               const float light[3]) {
  std::vector<RTCRay> rays(primary.size());
  for (size_t i = 0; i < primary.size(); ++i) {
    const RTCRay& p = primary[i];
    const float t = hitT[i];
    RTCRay& s = rays[i];
    s = p;
    if (!(t < std::numeric_limits<float>::infinity())) {
      s.tnear = 1.f;  // inactive: an empty segment
      s.tfar = 0.f;
      continue;
    }
    s.org_x = p.org_x + t * p.dir_x;
    s.org_y = p.org_y + t * p.dir_y;
    s.org_z = p.org_z + t * p.dir_z;
    s.dir_x = light[0] - s.org_x;
    s.dir_y = light[1] - s.org_y;
    s.dir_z = light[2] - s.org_z;
    s.tnear = 1e-3f;
    s.tfar = 1.f;
  }
  return rays;
}

std::vector<RTCRay> diffuseBounceRays(const std::vector<RTCRayHit>& primaryHits, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::vector<RTCRay> rays;
  for (const RTCRayHit& h : primaryHits) {
    if (h.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    float n[3] = {h.hit.Ng_x, h.hit.Ng_y, h.hit.Ng_z};
    if (!(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0.f)) continue;
    normalize(n);
    if (n[0] * h.ray.dir_x + n[1] * h.ray.dir_y + n[2] * h.ray.dir_z > 0.f)
      for (float& c : n) c = -c;
    const float p[3] = {h.ray.org_x + h.ray.tfar * h.ray.dir_x, h.ray.org_y + h.ray.tfar * h.ray.dir_y,
                        h.ray.org_z + h.ray.tfar * h.ray.dir_z};
    float org[3];
    offsetRayOrigin(p, n, org);
    // Cosine-weighted hemisphere around n (Malley's method) in an orthonormal frame.
    const float helper[3] = {std::fabs(n[0]) < 0.9f ? 1.f : 0.f, std::fabs(n[0]) < 0.9f ? 0.f : 1.f, 0.f};
    float t[3], b[3];
    crossf(n, helper, t);
    normalize(t);
    crossf(n, t, b);
    const float r = std::sqrt(unit(rng)), phi = 6.2831853f * unit(rng);
    const float x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(std::max(0.f, 1.f - r * r));
    const float dir[3] = {x * t[0] + y * b[0] + z * n[0], x * t[1] + y * b[1] + z * n[1], x * t[2] + y * b[2] + z * n[2]};
    rays.push_back(makeRay(org, dir));
  }
  return rays;
}

}  // namespace obvh::tools
