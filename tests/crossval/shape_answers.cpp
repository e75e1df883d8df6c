#include "shape_answers.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hit_compare.h"

namespace obvh::test {

namespace {
std::string describeNg(const RTCHit& h) {
  return "(" + std::to_string(h.Ng_x) + ", " + std::to_string(h.Ng_y) + ", " + std::to_string(h.Ng_z) + ")";
}
}  // namespace

ShapeAnswerCounts compareShapeAnswers(RTCScene reference, RTCScene candidate, const std::vector<RTCRay>& rays,
                                      const ShapeAnswerRules& rules) {
  const LoadedLibraries& libs = libraries();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  ShapeAnswerCounts counts;
  for (const RTCRay& ray : rays) {
    RTCRayHit rh[2];
    RTCRay occluded[2];
    for (int k = 0; k < 2; ++k) {
      rh[k].ray = ray;
      rh[k].hit.geomID = rh[k].hit.primID = RTC_INVALID_GEOMETRY_ID;
      (k ? libs.obvh : libs.embree)->rtcIntersect1(k ? candidate : reference, &context, &rh[k]);
      occluded[k] = ray;
      (k ? libs.obvh : libs.embree)->rtcOccluded1(k ? candidate : reference, &context, &occluded[k]);
      counts.hits[k] += rh[k].hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    const RTCHit& e = rh[0].hit;
    const RTCHit& o = rh[1].hit;
    const auto grazes = [&](const RTCHit& h) { return h.geomID != RTC_INVALID_GEOMETRY_ID && rules.grazes(ray, h); };
    const bool sameAnswer = e.geomID == o.geomID && e.primID == o.primID;
    if (!sameAnswer && rules.jointTie && rules.jointTie(rh[0], rh[1])) {
      ++counts.joints;
      continue;
    }
    const bool occlusionAgrees = (occluded[0].tfar < 0.f) == (occluded[1].tfar < 0.f);
    if (!sameAnswer || !occlusionAgrees) {
      if (grazes(e) || grazes(o)) {
        ++counts.grazing;
        continue;
      }
      counts.mismatched += !sameAnswer;
      counts.occlusionMismatched += !occlusionAgrees;
      if (counts.firstMismatch.empty()) counts.firstMismatch = tools::describeRay(ray);
      continue;
    }
    if (e.geomID == RTC_INVALID_GEOMETRY_ID) continue;
    const float te = rh[0].ray.tfar, to = rh[1].ray.tfar;
    const float scale = rules.ngTolerance * std::max({std::fabs(e.Ng_x), std::fabs(e.Ng_y), std::fabs(e.Ng_z), 1e-3f});
    const bool close = std::fabs(te - to) <= 1e-4f * std::max(1.f, te) && std::fabs(e.u - o.u) <= rules.uTolerance &&
                       std::fabs(e.v - o.v) <= rules.vTolerance && std::fabs(e.Ng_x - o.Ng_x) <= scale &&
                       std::fabs(e.Ng_y - o.Ng_y) <= scale && std::fabs(e.Ng_z - o.Ng_z) <= scale;
    if (!close && !grazes(e)) {
      ++counts.mismatched;
      if (counts.firstMismatch.empty())
        counts.firstMismatch = tools::describeRay(ray) + " (values differ: t " + std::to_string(te) + " / " +
                               std::to_string(to) + ", u " + std::to_string(e.u) + " / " + std::to_string(o.u) + ", v " +
                               std::to_string(e.v) + " / " + std::to_string(o.v) + ", Ng " + describeNg(e) + " / " +
                               describeNg(o) + ")";
    }
  }
  return counts;
}

void expectSameShapeAnswers(const char* what, const ShapeAnswerCounts& counts, size_t rayCount, size_t minimumHits) {
  std::printf("[crossval] %s: %zu rays, Embree %zu hits, obvh %zu hits, %zu grazing silhouettes, %zu joint ties, "
              "%zu mismatches, %zu occlusion mismatches\n",
              what, rayCount, counts.hits[0], counts.hits[1], counts.grazing, counts.joints, counts.mismatched,
              counts.occlusionMismatched);
  EXPECT_GT(counts.hits[0], minimumHits);
  EXPECT_EQ(counts.mismatched, 0u) << counts.firstMismatch;
  EXPECT_EQ(counts.occlusionMismatched, 0u) << counts.firstMismatch;
}

}  // namespace obvh::test
