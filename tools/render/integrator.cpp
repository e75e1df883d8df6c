#include "integrator.h"

#include <cmath>
#include <limits>

#include "offset_ray.h"
#include "spectral.h"
#include "surface.h"

namespace obvh::render {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

RTCRayHit makeRayHit(Vec3 org, Vec3 dir, float tnear, float tfar) {
  RTCRayHit r{};
  r.ray.org_x = org.x, r.ray.org_y = org.y, r.ray.org_z = org.z;
  r.ray.dir_x = dir.x, r.ray.dir_y = dir.y, r.ray.dir_z = dir.z;
  r.ray.tnear = tnear, r.ray.tfar = tfar;
  r.ray.mask = 0xFFFFFFFFu;
  r.hit.geomID = r.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return r;
}

// Origin just off the surface on the side of `side` (a unit normal), without self-intersection.
Vec3 offsetOrigin(Vec3 p, Vec3 side) {
  const float in[3] = {p.x, p.y, p.z}, n[3] = {side.x, side.y, side.z};
  float out[3];
  tools::offsetRayOrigin(in, n, out);
  return {out[0], out[1], out[2]};
}

float fresnelDielectric(float cosIncident, float eta) {  // eta = n_transmitted / n_incident
  const float sin2 = std::max(0.f, 1.f - cosIncident * cosIncident) / (eta * eta);
  if (sin2 >= 1.f) return 1.f;
  const float cosT = std::sqrt(1.f - sin2);
  const float rs = (cosIncident - eta * cosT) / (cosIncident + eta * cosT);
  const float rp = (eta * cosIncident - cosT) / (eta * cosIncident + cosT);
  return 0.5f * (rs * rs + rp * rp);
}

Vec3 cosineDirection(Vec3 n, Sampler& sampler) {
  const float r = std::sqrt(sampler.next1D()), phi = 2.f * kPi * sampler.next1D();
  Vec3 t, b;
  orthonormalBasis(n, t, b);
  const float x = r * std::cos(phi), y = r * std::sin(phi);
  return normalize(t * x + b * y + n * std::sqrt(std::max(0.f, 1.f - x * x - y * y)));
}

}  // namespace

Integrator::Integrator(const tools::RtcLibrary& lib, const CommittedRenderScene& committed, const RenderScene& scene,
                       const ScenePose& pose, const EffectPlan& plan, const IntegratorSettings& settings)
    : lib_(lib), committed_(committed), scene_(scene), pose_(pose), plan_(plan), settings_(settings) {
  environment_ = pose.lights.empty() ? (plan.pathTracing ? 1.f : 0.05f) : 0.02f;
}

bool Integrator::intersect(Vec3 org, Vec3 dir, float tfar, RTCRayHit& rayhit, uint64_t& rays, bool cameraRay) const {
  rayhit = makeRayHit(org, dir, 0.f, tfar);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  if (cameraRay) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const RTCRayHit query = rayhit;
  lib_.rtcIntersect1(committed_.handle(), &context, &rayhit);
  ++rays;
  if (log_) log_->push_back({false, query, rayhit});
  return rayhit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

bool Integrator::occluded(Vec3 org, Vec3 dir, float tfar, uint64_t& rays) const {
  RTCRayHit r = makeRayHit(org, dir, 0.f, tfar);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  const RTCRayHit query = r;
  lib_.rtcOccluded1(committed_.handle(), &context, &r.ray);
  ++rays;
  if (log_) log_->push_back({true, query, r});
  return r.ray.tfar < 0.f;  // Embree marks an occluded ray with tfar = -inf
}

float Integrator::transmittance(Vec3 org, Vec3 dir, float distance, uint64_t& rays) const {
  if (!plan_.transparency) return occluded(org, dir, distance, rays) ? 0.f : 1.f;
  // Through alpha layers, nearest first.
  float through = 1.f;
  for (int layer = 0; layer < settings_.maxLayers && through > 1.f / 1024.f; ++layer) {
    RTCRayHit r;
    if (!intersect(org, dir, distance, r, rays)) return through;
    const Surface s = surfaceAt(scene_, pose_, committed_.locate(r.hit), r);
    through *= 1.f - effectiveAlpha(s);
    distance -= r.ray.tfar;
    org = offsetOrigin(s.position, -s.geometricNormal);
  }
  return through > 1.f / 1024.f ? through : 0.f;
}

Vec3 Integrator::directLight(const Surface& s, uint64_t& rays) const {
  Vec3 sum{0.f};
  for (const PlacedLight& placed : pose_.lights) {
    const Light& light = scene_.lights[size_t(placed.light)];
    Vec3 toLight;
    float distance = kInfinity, falloff = 1.f;
    if (light.type == LightType::Directional) {
      toLight = -placed.direction;
    } else {
      const Vec3 d = placed.position - s.position;
      distance = length(d);
      if (distance <= 0.f) continue;
      toLight = d / distance;
      falloff = 1.f / (distance * distance);
      if (light.range > 0.f) {  // glTF's recommended smooth window to zero at the range
        const float ratio = distance / light.range;
        const float window = std::max(0.f, std::min(1.f, 1.f - ratio * ratio * ratio * ratio));
        falloff *= window * window;
      }
      if (light.type == LightType::Spot) {
        const float cosOuter = std::cos(light.outerConeAngle), cosInner = std::cos(light.innerConeAngle);
        const float c = dot(-toLight, placed.direction);
        const float t = std::min(1.f, std::max(0.f, (c - cosOuter) / std::max(cosInner - cosOuter, 1e-4f)));
        falloff *= t * t;
      }
    }
    const float cosine = dot(s.shadingNormal, toLight);
    if (cosine <= 0.f || dot(s.geometricNormal, toLight) <= 0.f || falloff <= 0.f) continue;
    const float visible = plan_.shadows ? transmittance(offsetOrigin(s.position, s.geometricNormal), toLight,
                                                        distance == kInfinity ? kInfinity : distance * (1.f - 1e-4f), rays)
                                        : 1.f;
    if (visible > 0.f) sum += light.color * (light.intensity * falloff * cosine * visible / kPi);
  }
  return sum;
}

Vec3 Integrator::shadeDirect(Vec3 org, Vec3 dir, uint64_t& rays) const {
  Vec3 result{0.f};
  float through = 1.f;
  for (int layer = 0; layer < settings_.maxLayers; ++layer) {
    RTCRayHit r;
    // Every layer continues the camera ray in its direction.
    if (!intersect(org, dir, kInfinity, r, rays, true)) return result + Vec3(environment_) * through;
    const Surface s = surfaceAt(scene_, pose_, committed_.locate(r.hit), r);
    const float alpha = plan_.transparency ? effectiveAlpha(s) : 1.f;
    if (alpha > 0.f) {
      Vec3 lit = s.emission;
      if (pose_.lights.empty()) {
        const float facing = std::fabs(dot(s.shadingNormal, dir));
        lit += s.baseColor * (settings_.headlightAmbient + (1.f - settings_.headlightAmbient) * facing);
      } else {
        lit += s.baseColor * (Vec3(settings_.headlightAmbient * environment_) + directLight(s, rays));
      }
      result += lit * (alpha * through);
      through *= 1.f - alpha;
    }
    if (through <= 1.f / 1024.f) return result;
    org = offsetOrigin(s.position, -s.geometricNormal);  // continue behind the layer
  }
  return result;
}

Vec3 Integrator::tracePath(Vec3 org, Vec3 dir, Sampler& sampler, float wavelength, uint64_t& rays) const {
  const bool spectral = wavelength > 0.f;
  // In spectral mode the components of these carry the same single-wavelength value.
  const auto colour = [&](Vec3 rgb) { return spectral ? Vec3(rgbSpectrumAt(rgb, wavelength)) : rgb; };
  Vec3 result{0.f}, throughput{1.f};
  for (int depth = 0; depth < settings_.maxDepth; ++depth) {
    RTCRayHit r;
    if (!intersect(org, dir, kInfinity, r, rays, depth == 0)) return result + throughput * environment_;
    const Surface s = surfaceAt(scene_, pose_, committed_.locate(r.hit), r);
    if (plan_.transparency && sampler.next1D() >= effectiveAlpha(s)) {
      org = offsetOrigin(s.position, -s.geometricNormal);
      --depth;  // passing an alpha hole is not a bounce, but stay bounded
      if (depth < -settings_.maxLayers) return result;
      continue;
    }
    result += throughput * colour(s.emission);
    if (sampler.next1D() < s.material->transmission) {
      // Dielectric boundary: the geometric side tells whether the path enters or leaves the volume.
      const float ior = spectral ? iorAtWavelength(s.material->ior, s.material->dispersion, wavelength) : s.material->ior;
      const float eta = s.frontFace ? ior : 1.f / ior;
      const Vec3 n = s.shadingNormal;
      const float cosI = std::min(1.f, std::fabs(dot(dir, n)));
      if (sampler.next1D() < fresnelDielectric(cosI, eta)) {
        dir = normalize(dir + n * (2.f * cosI));
        org = offsetOrigin(s.position, s.geometricNormal);
      } else {
        const float k = 1.f / eta;
        const float cosT = std::sqrt(std::max(0.f, 1.f - k * k * (1.f - cosI * cosI)));
        dir = normalize(dir * k + n * (k * cosI - cosT));
        org = offsetOrigin(s.position, -s.geometricNormal);
        if (s.frontFace) throughput *= colour(s.baseColor);
      }
      continue;
    }
    const Vec3 albedo = colour(s.baseColor);
    if (!pose_.lights.empty()) {
      const Vec3 light = directLight(s, rays);
      result += throughput * albedo * (spectral ? Vec3(rgbSpectrumAt(light, wavelength)) : light);
    }
    throughput *= albedo;
    if (maxComponent(throughput) <= 0.f) return result;
    dir = cosineDirection(s.shadingNormal, sampler);
    if (dot(dir, s.geometricNormal) <= 0.f) return result;
    org = offsetOrigin(s.position, s.geometricNormal);
  }
  return result;
}

Vec3 Integrator::radiance(Vec3 org, Vec3 dir, Sampler& sampler, float spectralU, uint64_t& rays) const {
  if (!plan_.pathTracing) return shadeDirect(org, dir, rays);
  if (!plan_.dispersion) return tracePath(org, dir, sampler, 0.f, rays);
  const float wavelength = kShortestWavelength + (kLongestWavelength - kShortestWavelength) * spectralU;
  return spectralSampleToRgb(tracePath(org, dir, sampler, wavelength, rays).x, wavelength);
}

}  // namespace obvh::render
