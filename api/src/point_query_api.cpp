// rtcPointQuery and its packet forms: the backend finds candidate primitives, this file runs the
// callback passed to rtcPointQuery and the geometry's own on each, with Embree's context (instance
// ID and transforms) and similarity scale (that of world-to-instance; 0 if not a similarity).
#include <embree3/rtcore.h>

#include "api_error.h"
#include "scene.h"
#include "traversal/point_query_callbacks.h"

using namespace obvh::api;

namespace {

void storeColumnMajor(const obvh::Affine3f& a, float m[16]) {
  const float values[16] = {a.vx.x, a.vx.y, a.vx.z, 0.f, a.vy.x, a.vy.y, a.vy.z, 0.f,
                            a.vz.x, a.vz.y, a.vz.z, 0.f, a.p.x,  a.p.y,  a.p.z,  1.f};
  for (int k = 0; k < 16; ++k) m[k] = values[k];
}

class PointQueryDispatch final : public obvh::PointQueryCallbacks {
 public:
  PointQueryDispatch(RTCPointQuery& query, RTCPointQueryContext& context, RTCPointQueryFunction fn, void* userPtr)
      : query_(query), context_(context), fn_(fn), userPtr_(userPtr) {}

  float radius() const override { return query_.radius; }
  float time() const override { return query_.time; }

  bool visit(const void* owner, uint32_t geomID, uint32_t primID, const obvh::PointQueryInstance* instance) override {
    const Scene& scene = *static_cast<const Scene*>(owner);
    const Geometry* geometry = scene.builtGeometry(geomID);
    // As in Embree, the function passed to rtcPointQuery runs first, then the geometry's own.
    const RTCPointQueryFunction own = geometry ? geometry->pointQueryFunction() : nullptr;
    if (!fn_ && !own) return false;
    const unsigned level = context_.instStackSize;
    if (instance) {
      if (level >= RTC_MAX_INSTANCE_LEVEL_COUNT) return false;
      context_.instID[level] = instance->geomID;
      storeColumnMajor(*instance->localToWorld, context_.inst2world[level]);
      storeColumnMajor(instance->localToWorld->inverse(), context_.world2inst[level]);
      context_.instStackSize = level + 1;
    }
    RTCPointQueryFunctionArguments args;
    args.query = &query_;  // always the world-space query, as in Embree
    args.userPtr = userPtr_;
    args.primID = primID;
    args.geomID = geomID;
    args.context = &context_;
    args.similarityScale = instance ? instance->similarityScale : 1.f;
    bool changed = false;
    if (fn_) changed |= fn_(&args);
    if (own) changed |= own(&args);
    if (instance) {
      context_.instStackSize = level;
      context_.instID[level] = RTC_INVALID_GEOMETRY_ID;
    }
    return changed;
  }

 private:
  RTCPointQuery& query_;
  RTCPointQueryContext& context_;
  RTCPointQueryFunction fn_;
  void* userPtr_;
};

bool queryOne(const Scene& scene, RTCPointQuery& query, RTCPointQueryContext& context, RTCPointQueryFunction fn,
              void* userPtr) {
  PointQueryDispatch dispatch(query, context, fn, userPtr);
  return scene.accel().pointQuery({query.x, query.y, query.z}, dispatch);
}

// Validates the arguments every point query shares and runs body with the committed scene.
template <typename Query, typename Body>
bool pointQuery(RTCScene handle, Query* query, RTCPointQueryContext* context, Body&& body) {
  Scene* scene = Scene::from(handle);
  return guarded(scene ? scene->device() : nullptr, false, [&] {
    requireHandle(scene);
    requireHandle(query);
    requireHandle(context);
    scene->requireCommitted();
    return body(*scene);
  });
}

template <int W, typename Packet>
bool queryPacket(const int* valid, RTCScene handle, Packet* query, RTCPointQueryContext* context,
                 RTCPointQueryFunction fn, void** userPtr) {
  return pointQuery(handle, query, context, [&](const Scene& scene) {
    bool changed = false;
    for (int i = 0; i < W; ++i) {
      if (valid && valid[i] != -1) continue;
      RTCPointQuery one{query->x[i], query->y[i], query->z[i], query->time[i], query->radius[i]};
      changed |= queryOne(scene, one, *context, fn, userPtr ? userPtr[i] : nullptr);
      query->radius[i] = one.radius;
    }
    return changed;
  });
}

}  // namespace

RTC_API bool rtcPointQuery(RTCScene handle, RTCPointQuery* query, RTCPointQueryContext* context,
                           RTCPointQueryFunction queryFunc, void* userPtr) {
  return pointQuery(handle, query, context,
                    [&](const Scene& scene) { return queryOne(scene, *query, *context, queryFunc, userPtr); });
}

RTC_API bool rtcPointQuery4(const int* valid, RTCScene scene, RTCPointQuery4* query, RTCPointQueryContext* context,
                            RTCPointQueryFunction queryFunc, void** userPtr) {
  return queryPacket<4>(valid, scene, query, context, queryFunc, userPtr);
}

RTC_API bool rtcPointQuery8(const int* valid, RTCScene scene, RTCPointQuery8* query, RTCPointQueryContext* context,
                            RTCPointQueryFunction queryFunc, void** userPtr) {
  return queryPacket<8>(valid, scene, query, context, queryFunc, userPtr);
}

RTC_API bool rtcPointQuery16(const int* valid, RTCScene scene, RTCPointQuery16* query, RTCPointQueryContext* context,
                             RTCPointQueryFunction queryFunc, void** userPtr) {
  return queryPacket<16>(valid, scene, query, context, queryFunc, userPtr);
}
