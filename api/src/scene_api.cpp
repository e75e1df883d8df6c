// rtc* entry points for scenes (everything except the ray queries).
#include <embree3/rtcore.h>

#include <cstring>

#include "api_error.h"
#include "enum_bits.h"
#include "scene.h"

using namespace obvh::api;

namespace {

Device* deviceOf(Scene* s) { return s ? s->device() : nullptr; }

template <typename Body>
void withScene(RTCScene handle, Body&& body) {
  Scene* s = Scene::from(handle);
  guarded(deviceOf(s), [&] { body(*requireHandle(s)); });
}

}  // namespace

RTC_API RTCScene rtcNewScene(RTCDevice device) {
  Device* d = Device::from(device);
  return guarded(d, RTCScene(nullptr), [&] { return (new Scene(requireHandle(d)))->handle(); });
}

RTC_API RTCDevice rtcGetSceneDevice(RTCScene scene) {
  Scene* s = Scene::from(scene);
  return guarded(deviceOf(s), RTCDevice(nullptr), [&] {
    Device* d = requireHandle(s)->device();
    d->retain();
    return d->handle();
  });
}

RTC_API void rtcRetainScene(RTCScene scene) { withScene(scene, [](Scene& s) { s.retain(); }); }
RTC_API void rtcReleaseScene(RTCScene scene) { withScene(scene, [](Scene& s) { s.release(); }); }

RTC_API unsigned int rtcAttachGeometry(RTCScene scene, RTCGeometry geometry) {
  Scene* s = Scene::from(scene);
  return guarded(deviceOf(s), RTC_INVALID_GEOMETRY_ID,
                 [&] { return requireHandle(s)->attach(requireHandle(Geometry::from(geometry))); });
}

RTC_API void rtcAttachGeometryByID(RTCScene scene, RTCGeometry geometry, unsigned int geomID) {
  withScene(scene, [&](Scene& s) { s.attachById(requireHandle(Geometry::from(geometry)), geomID); });
}

RTC_API void rtcDetachGeometry(RTCScene scene, unsigned int geomID) {
  withScene(scene, [&](Scene& s) { s.detach(geomID); });
}

RTC_API RTCGeometry rtcGetGeometry(RTCScene scene, unsigned int geomID) {
  Scene* s = Scene::from(scene);
  return guarded(deviceOf(s), RTCGeometry(nullptr), [&] {
    Geometry* g = requireHandle(s)->geometry(geomID);
    return g ? g->handle() : RTCGeometry(nullptr);
  });
}

RTC_API RTCGeometry rtcGetGeometryThreadSafe(RTCScene scene, unsigned int geomID) {
  return rtcGetGeometry(scene, geomID);  // the scene's lookup is already serialised by its mutex
}

RTC_API void rtcCommitScene(RTCScene scene) { withScene(scene, [](Scene& s) { s.commit(); }); }

// Each joining thread runs the same commit; the scene's mutex lets one build while the others
// wait, and the later ones find nothing left to rebuild.
RTC_API void rtcJoinCommitScene(RTCScene scene) { withScene(scene, [](Scene& s) { s.commit(); }); }

RTC_API void rtcSetSceneProgressMonitorFunction(RTCScene scene, RTCProgressMonitorFunction progress, void* ptr) {
  withScene(scene, [&](Scene& s) { s.setProgressMonitor(progress, ptr); });
}

RTC_API void rtcSetSceneBuildQuality(RTCScene scene, RTCBuildQuality quality) {
  withScene(scene, [&](Scene& s) { s.setBuildQuality(enumBits(quality)); });
}

RTC_API void rtcSetSceneFlags(RTCScene scene, RTCSceneFlags flags) {
  withScene(scene, [&](Scene& s) { s.setFlags(enumBits(flags)); });
}

RTC_API RTCSceneFlags rtcGetSceneFlags(RTCScene scene) {
  Scene* s = Scene::from(scene);
  return guarded(deviceOf(s), RTC_SCENE_FLAG_NONE, [&] {
    RTCSceneFlags flags;
    const int bits = requireHandle(s)->flags();
    std::memcpy(&flags, &bits, sizeof flags);  // hands back exactly the bits that were set
    return flags;
  });
}

RTC_API void rtcGetSceneBounds(RTCScene scene, RTCBounds* bounds_o) {
  withScene(scene, [&](Scene& s) {
    requireHandle(bounds_o);
    s.requireCommitted();
    *bounds_o = s.bounds();
  });
}

// obvh has no motion blur yet, so a committed scene's bounds are the same at both ends of time.
RTC_API void rtcGetSceneLinearBounds(RTCScene scene, RTCLinearBounds* bounds_o) {
  withScene(scene, [&](Scene& s) {
    requireHandle(bounds_o);
    s.requireCommitted();
    *bounds_o = s.linearBounds();
  });
}

RTC_API void rtcCollide(RTCScene scene0, RTCScene, RTCCollideFunc, void*) {
  withScene(scene0, [](Scene&) { fail(RTC_ERROR_INVALID_OPERATION, "rtcCollide is not supported by obvh yet"); });
}
