// Ray sets used by the benchmark and the cross-validation.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <vector>

namespace obvh::tools {

struct SceneBox {
  float lower[3];
  float upper[3];
};

// Pinhole camera looking at the box centre from a fixed diagonal direction, framing the whole box.
std::vector<RTCRay> perspectiveRays(const SceneBox& box, int width, int height);

// Orthographic camera along -z through the box (coherent, parallel rays).
std::vector<RTCRay> orthographicRays(const SceneBox& box, int width, int height);

// Random origins around the box aimed at random points inside it (incoherent), seeded.
std::vector<RTCRay> randomRays(const SceneBox& box, size_t count, uint32_t seed);

// Rays leaving one point (a transmitter) in uniformly distributed directions, seeded.
std::vector<RTCRay> pointSourceRays(const float source[3], size_t count, uint32_t seed);

// Rays from the hit points of primary rays towards a point light (shadow rays); misses get tfar < tnear.
std::vector<RTCRay> shadowRays(const std::vector<RTCRay>& primary, const std::vector<float>& hitT,
                               const float light[3]);

// The benchmarks' shadow rays: from the hits of the primary rays (records as rtcIntersect1 left
// them) towards a light above and beside the scene's box.
std::vector<RTCRay> shadowRaysTowardsSceneLight(const std::vector<RTCRay>& primary,
                                                const std::vector<RTCRayHit>& hits, const SceneBox& box);

// One cosine-distributed diffuse bounce from each hit of the primary rays (misses spawn nothing),
// leaving the surface on the side the primary ray came from; seeded.
std::vector<RTCRay> diffuseBounceRays(const std::vector<RTCRayHit>& primaryHits, uint32_t seed);

}  // namespace obvh::tools
