#include "query_dispatch.h"

#include <limits>

namespace obvh::api {
namespace {

// Embree pushes the current instance ID into the context while it traverses an instance, so
// callbacks can read it; this does the same for the duration of one callback.
class InstanceIdScope {
 public:
  InstanceIdScope(RTCIntersectContext& context, uint32_t instID) : context_(context), saved_(context.instID[0]) {
    context_.instID[0] = instID;
  }
  ~InstanceIdScope() { context_.instID[0] = saved_; }

 private:
  RTCIntersectContext& context_;
  unsigned saved_;
};

RTCHit embreeHit(const Hit& hit) {
  RTCHit out{};
  out.Ng_x = hit.Ng.x, out.Ng_y = hit.Ng.y, out.Ng_z = hit.Ng.z;
  out.u = hit.u, out.v = hit.v;
  out.primID = hit.primID;
  out.geomID = hit.geomID;
  out.instID[0] = hit.instID;
  return out;
}

Hit backendHit(const RTCHit& hit) {
  Hit out;
  out.Ng = {hit.Ng_x, hit.Ng_y, hit.Ng_z};
  out.u = hit.u, out.v = hit.v;
  out.primID = hit.primID;
  out.geomID = hit.geomID;
  out.instID = hit.instID[0];
  return out;
}

Ray backendRay(const RTCRay& r, bool masksOn) {
  Ray ray;
  ray.org = {r.org_x, r.org_y, r.org_z};
  ray.dir = {r.dir_x, r.dir_y, r.dir_z};
  ray.tnear = r.tnear;
  ray.tfar = r.tfar;
  ray.mask = masksOn ? r.mask : 0xFFFFFFFFu;
  return ray;
}

}  // namespace

QueryDispatch::QueryDispatch(const Scene& scene, RTCIntersectContext& context)
    : scene_(scene), context_(context), masksOn_(scene.device()->config().rayMasks) {
  state_.contextFilter = (scene.flags() & RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION) && context.filter;
  // Most scenes have no filters and no user geometry; their queries never leave the backend.
  if (scene.needsCallbacks() || state_.contextFilter) state_.callbacks = this;
  state_.instID = context.instID[0];
}

RTCRay QueryDispatch::embreeRay(const Ray& ray, float tfar) const {
  RTCRay r = *original_;
  r.org_x = ray.org.x, r.org_y = ray.org.y, r.org_z = ray.org.z;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.tnear = ray.tnear;
  r.tfar = tfar;
  return r;
}

bool QueryDispatch::intersect(RTCRayHit& rayhit) {
  original_ = &rayhit.ray;
  Ray ray = backendRay(rayhit.ray, masksOn_);
  Hit hit;
  if (!scene_.accel().intersect(ray, hit, state_)) return false;
  rayhit.ray.tfar = ray.tfar;
  rayhit.hit = embreeHit(hit);
  return true;
}

bool QueryDispatch::occluded(RTCRay& ray) {
  original_ = &ray;
  if (!scene_.accel().occluded(backendRay(ray, masksOn_), state_)) return false;
  ray.tfar = -std::numeric_limits<float>::infinity();
  return true;
}

void QueryDispatch::runFilters(const Geometry& geometry, const RTCFilterFunctionNArguments* args,
                               bool occlusion) const {
  const RTCFilterFunctionN geometryFilter = occlusion ? geometry.occludedFilter() : geometry.intersectFilter();
  if (geometryFilter) geometryFilter(args);
  if (!state_.contextFilter) return;
  bool anyValid = false;
  for (unsigned i = 0; i < args->N; ++i) anyValid |= args->valid[i] != 0;
  if (anyValid) context_.filter(args);
}

bool QueryDispatch::acceptHit(const void* owner, const Ray& ray, const Hit& candidate, float t, bool occlusion) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(candidate.geomID);
  RTCRayHit rayhit;
  rayhit.ray = embreeRay(ray, t);
  rayhit.hit = embreeHit(candidate);
  int valid = -1;
  const RTCFilterFunctionNArguments args{&valid, geometry.userData(), &context_,
                                         reinterpret_cast<RTCRayN*>(&rayhit.ray),
                                         reinterpret_cast<RTCHitN*>(&rayhit.hit), 1};
  InstanceIdScope scope(context_, candidate.instID);
  runFilters(geometry, &args, occlusion);
  return valid != 0;
}

bool QueryDispatch::intersectUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, Hit& hit,
                                  const QueryState& state) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(geomID);
  if (!geometry.user().intersect) return false;
  RTCRayHit rayhit;
  rayhit.ray = embreeRay(ray, ray.tfar);
  rayhit.hit = embreeHit(hit);
  int valid = -1;
  UserIntersectArguments args;
  fillUserArguments(args, &valid, geometry, geomID, primID);
  args.rayhit = reinterpret_cast<RTCRayHitN*>(&rayhit);
  {
    InstanceIdScope scope(context_, state.instID);
    geometry.user().intersect(&args);
  }
  // The callback reports a hit by writing the ray's tfar and hit, as it would into Embree's ray.
  if (rayhit.ray.tfar == ray.tfar && rayhit.hit.geomID == hit.geomID && rayhit.hit.primID == hit.primID) return false;
  ray.tfar = rayhit.ray.tfar;
  hit = backendHit(rayhit.hit);
  return true;
}

bool QueryDispatch::occludedUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray,
                                 const QueryState& state) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(geomID);
  if (!geometry.user().occluded) return false;
  RTCRay r = embreeRay(ray, ray.tfar);
  int valid = -1;
  UserOccludedArguments args;
  fillUserArguments(args, &valid, geometry, geomID, primID);
  args.ray = reinterpret_cast<RTCRayN*>(&r);
  {
    InstanceIdScope scope(context_, state.instID);
    geometry.user().occluded(&args);
  }
  return r.tfar == -std::numeric_limits<float>::infinity();
}

}  // namespace obvh::api

using namespace obvh::api;

// Called by user-geometry callbacks with the arguments obvh passed them (see UserIntersectArguments).
RTC_API void rtcFilterIntersection(const RTCIntersectFunctionNArguments* args,
                                   const RTCFilterFunctionNArguments* filterArgs) {
  if (!args || !filterArgs) return reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  const auto* ours = static_cast<const UserIntersectArguments*>(args);
  ours->dispatch->runFilters(*ours->geometry, filterArgs, false);
}

RTC_API void rtcFilterOcclusion(const RTCOccludedFunctionNArguments* args,
                                const RTCFilterFunctionNArguments* filterArgs) {
  if (!args || !filterArgs) return reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  const auto* ours = static_cast<const UserOccludedArguments*>(args);
  ours->dispatch->runFilters(*ours->geometry, filterArgs, true);
}
