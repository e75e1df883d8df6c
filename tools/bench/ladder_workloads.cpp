#include "ladder_workloads.h"

namespace obvh::tools {

std::vector<Workload> ladderWorkloads(const RtcLibrary& embree, RTCScene embreeScene, size_t randomRayCount) {
  RTCBounds b;
  embree.rtcGetSceneBounds(embreeScene, &b);
  const SceneBox box{{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
  std::vector<Workload> workloads;
  workloads.push_back({"primary perspective", "primary", TracedQuery::Intersect1, perspectiveRays(box, 1024, 768)});
  workloads.push_back({"random (incoherent)", "random", TracedQuery::Intersect1, randomRays(box, randomRayCount, 12345u)});
  const float centre[3] = {0.5f * (b.lower_x + b.upper_x), 0.5f * (b.lower_y + b.upper_y), 0.5f * (b.lower_z + b.upper_z)};
  workloads.push_back(
      {"from a point source", "point", TracedQuery::Intersect1, pointSourceRays(centre, randomRayCount, 4242u)});
  std::vector<RTCRayHit> hits;
  traceIntersectMrays(embree, embreeScene, workloads[0].rays, 1, &hits);
  workloads.push_back({"shadow (occluded)", "shadow", TracedQuery::Occluded1,
                       shadowRaysTowardsSceneLight(workloads[0].rays, hits, box)});
  // The rest of the floor rows of the main bench (issue 4): camera and shadow rays with Embree's
  // coherence hint, diffuse bounces, and coherent rtcIntersect8 packets of perspective and of
  // orthographic camera rays, with the main bench's rays; the perspective packets also copied one by
  // one into a single packet, as an application that fills one packet on its stack traces them.
  constexpr RTCIntersectContextFlags kCoherent = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  workloads.push_back({"camera, hint", "camera-hint", TracedQuery::Intersect1, workloads[0].rays, kCoherent});
  workloads.push_back({"shadow, hint", "shadow-hint", TracedQuery::Occluded1, workloads[3].rays, kCoherent});
  workloads.push_back({"diffuse bounce", "diffuse", TracedQuery::Intersect1, diffuseBounceRays(hits, 777u)});
  workloads.push_back({"packets of 8, hint", "packets8-hint", TracedQuery::Intersect8, workloads[0].rays, kCoherent});
  workloads.push_back({"orthographic packets of 8, hint", "packets8-ortho", TracedQuery::Intersect8,
                       orthographicRays(box, 1024, 768), kCoherent});
  workloads.push_back({"packets of 8 from one slot, hint", "packets8-slot", TracedQuery::Intersect8OneSlot,
                       workloads[0].rays, kCoherent});
  // The main bench's coherent stream row, with its rays (not a floor row of issue 4).
  workloads.push_back({"streams of 64, hint", "streams64-hint", TracedQuery::Intersect1M, workloads[0].rays, kCoherent});
  return workloads;
}

}  // namespace obvh::tools
