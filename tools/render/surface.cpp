#include "surface.h"

#include <algorithm>

namespace obvh::render {

Surface surfaceAt(const RenderScene& scene, const ScenePose& pose, const HitLocation& where, const RTCRayHit& rayhit) {
  const PlacedMesh& placed = pose.meshes.at(size_t(where.placement));
  const Primitive& p = scene.meshes[size_t(placed.mesh)].primitives.at(size_t(where.primitive));
  const uint32_t* tri = &p.indices.at(size_t(rayhit.hit.primID) * 3);
  const auto position = [&](uint32_t v) {
    return transformPoint(placed.toWorld, {p.positions[3 * v], p.positions[3 * v + 1], p.positions[3 * v + 2]});
  };
  const Vec3 v0 = position(tri[0]), v1 = position(tri[1]), v2 = position(tri[2]);
  const float u = rayhit.hit.u, v = rayhit.hit.v, w = 1.f - u - v;
  const Vec3 dir{rayhit.ray.dir_x, rayhit.ray.dir_y, rayhit.ray.dir_z};

  Surface s;
  s.position = Vec3{rayhit.ray.org_x, rayhit.ray.org_y, rayhit.ray.org_z} + dir * rayhit.ray.tfar;
  Vec3 ng = normalize(cross(v1 - v0, v2 - v0));
  s.frontFace = dot(ng, dir) < 0.f;
  if (!s.frontFace) ng = -ng;
  s.geometricNormal = ng;
  s.shadingNormal = ng;
  if (!p.normals.empty()) {
    const auto normal = [&](uint32_t i) { return Vec3{p.normals[3 * i], p.normals[3 * i + 1], p.normals[3 * i + 2]}; };
    Vec3 n = transformNormal(placed.toWorld, normal(tri[0]) * w + normal(tri[1]) * u + normal(tri[2]) * v);
    if (dot(n, ng) < 0.f) n = -n;
    s.shadingNormal = n;
  }
  s.material = &scene.material(p.material);
  float colour[4] = {s.material->baseColor[0], s.material->baseColor[1], s.material->baseColor[2], s.material->baseColor[3]};
  s.emission = s.material->emissive;
  if (!p.uvs.empty()) {
    const auto uv = [&](uint32_t i, int c) { return p.uvs[2 * i + size_t(c)]; };
    const float tu = uv(tri[0], 0) * w + uv(tri[1], 0) * u + uv(tri[2], 0) * v;
    const float tv = uv(tri[0], 1) * w + uv(tri[1], 1) * u + uv(tri[2], 1) * v;
    float texel[4];
    if (s.material->baseColorTexture >= 0) {
      scene.textures[size_t(s.material->baseColorTexture)].sample(tu, tv, texel);
      for (int c = 0; c < 4; ++c) colour[c] *= texel[c];
    }
    if (s.material->emissiveTexture >= 0 && maxComponent(s.emission) > 0.f) {
      scene.textures[size_t(s.material->emissiveTexture)].sample(tu, tv, texel);
      s.emission *= Vec3{texel[0], texel[1], texel[2]};
    }
  }
  s.baseColor = {colour[0], colour[1], colour[2]};
  s.alpha = colour[3];
  return s;
}

float effectiveAlpha(const Surface& surface) {
  switch (surface.material->alphaMode) {
    case AlphaMode::Opaque: return 1.f;
    case AlphaMode::Mask: return surface.alpha >= surface.material->alphaCutoff ? 1.f : 0.f;
    case AlphaMode::Blend: return std::min(std::max(surface.alpha, 0.f), 1.f);
  }
  return 1.f;
}

}  // namespace obvh::render
