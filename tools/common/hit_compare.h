// Compares two libraries' answers for one ray. Different answers are accepted only when a
// double-precision intersection shows the ray is ambiguous: it passes within a few ulps of a
// primitive's edge or vertex, or the competing hits lie at the same distance.
#pragma once

#include <embree3/rtcore.h>

#include <string>
#include <vector>

#include "scene_data.h"

namespace obvh::tools {

struct CompareTolerance {
  float tRelative = 1e-5f;
  float uvAbsolute = 1e-4f;
  float normalRelative = 1e-5f;
  // Distance to an edge, in ulps of the scene's coordinate magnitude, below which a hit is ambiguous.
  double edgeUlps = 4.0;
};

enum class Verdict { Equal, Ambiguous, Mismatch };

struct Comparison {
  Verdict verdict = Verdict::Equal;
  std::string reason;  // why the answers differ (empty when equal)
};

// ray: the query as it was before tracing. reference and candidate: the two libraries' hits.
Comparison compareHits(const SceneData& scene, const RTCRay& ray, const HitRecord& reference,
                       const HitRecord& candidate, const CompareTolerance& tolerance = {});

// One triangle of a primitive (quads have two) intersected in double precision.
struct ExactPart {
  bool planeHit = false;       // the ray's line meets the triangle's plane
  double t = 0.0;
  double u = 0.0, v = 0.0;     // in Embree's convention (quads: the quad's own parameterisation)
  double edgeDistance = 0.0;   // in-plane distance of the hit point to the boundary, positive inside
  double lineToEdges = 0.0;    // 3D distance between the ray's line and the triangle's edges
  double cosine = 0.0;         // |cos| of the angle between the ray and the triangle's normal
  double minHeight = 0.0;      // smallest altitude of the triangle
};
std::vector<ExactPart> intersectExact(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID);

// Ground truth for an occlusion query by brute force over every enabled primitive in double precision.
enum class OcclusionTruth { Occluded, Free, Ambiguous };
OcclusionTruth exactOcclusion(const SceneData& scene, const RTCRay& ray, const CompareTolerance& tolerance = {});

// Two libraries' occlusion answers for one ray. Different answers are accepted (Ambiguous) when the
// brute-force double-precision test finds the ray borderline, or when it agrees with the candidate;
// a candidate contradicting a clear double-precision answer is a Mismatch.
Comparison compareOcclusion(const SceneData& scene, const RTCRay& ray, bool referenceOccluded, bool candidateOccluded,
                            const CompareTolerance& tolerance = {});
// The same verdict from an exactOcclusion answer already at hand (callers judging many rows of the same rays).
Comparison judgeOcclusion(OcclusionTruth truth, bool referenceOccluded, bool candidateOccluded);

// Whether a library may report a hit on (geomID, primID) for this ray: false only when double
// precision proves the ray's line passes outside the primitive, or meets it outside (tnear, tfar],
// by more than rounding the float inputs can explain.
bool hitIsPlausible(const SceneData& scene, const RTCRay& ray, unsigned geomID, unsigned primID,
                    const CompareTolerance& tolerance = {});

std::string describeRay(const RTCRay& ray);
// The primitive's vertices in hex floats.
std::string describePrimitive(const SceneData& scene, unsigned geomID, unsigned primID);  // hex floats, so a failure can be replayed exactly

}  // namespace obvh::tools
