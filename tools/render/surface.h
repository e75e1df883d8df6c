// What shading needs to know about a hit, computed from the scene's own data (so it is the same
// whichever library found the hit): world position, normals facing the incoming ray, material,
// base colour and alpha after the texture lookup.
#pragma once

#include <embree3/rtcore.h>

#include "committed_scene.h"
#include "render_scene.h"

namespace obvh::render {

struct Surface {
  Vec3 position;
  Vec3 geometricNormal;  // unit, on the side the ray came from
  Vec3 shadingNormal;    // unit, interpolated vertex normal turned to the same side (geometric when none)
  bool frontFace = true; // the ray hit the side the triangle's winding faces
  const Material* material = nullptr;
  Vec3 baseColor;
  Vec3 emission;  // emissive factor times the emissive texture
  float alpha = 1.f;
};

Surface surfaceAt(const RenderScene& scene, const ScenePose& pose, const HitLocation& where, const RTCRayHit& rayhit);

// Alpha as the material's alpha mode applies it: MASK makes it 0 or 1, OPAQUE 1.
float effectiveAlpha(const Surface& surface);

}  // namespace obvh::render
