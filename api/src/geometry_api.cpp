// rtc* entry points for geometries (triangle and quad meshes in this slice).
#include <embree3/rtcore.h>

#include <string>

#include "api_error.h"
#include "geometry.h"

using namespace obvh::api;

namespace {

Device* deviceOf(Geometry* g) { return g ? g->device() : nullptr; }

bool isKnownGeometryType(RTCGeometryType type) {
  switch (type) {
    case RTC_GEOMETRY_TYPE_TRIANGLE: case RTC_GEOMETRY_TYPE_QUAD: case RTC_GEOMETRY_TYPE_GRID:
    case RTC_GEOMETRY_TYPE_SUBDIVISION:
    case RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE: case RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE: case RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE: case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE: case RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE:
    case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE: case RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE: case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_HERMITE_CURVE:
    case RTC_GEOMETRY_TYPE_SPHERE_POINT: case RTC_GEOMETRY_TYPE_DISC_POINT:
    case RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT: case RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE: case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_CATMULL_ROM_CURVE:
    case RTC_GEOMETRY_TYPE_USER: case RTC_GEOMETRY_TYPE_INSTANCE:
      return true;
  }
  return false;
}

// Runs body on a non-null geometry, reporting errors on its device.
template <typename Body>
void withGeometry(RTCGeometry handle, Body&& body) {
  Geometry* g = Geometry::from(handle);
  guarded(deviceOf(g), [&] { body(*requireHandle(g)); });
}

// Operations that belong to geometry types obvh does not implement yet.
void failForThisGeometry(RTCGeometry handle) {
  withGeometry(handle, [](Geometry&) { fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry"); });
}

}  // namespace

RTC_API RTCGeometry rtcNewGeometry(RTCDevice device, RTCGeometryType type) {
  Device* d = Device::from(device);
  return guarded(d, RTCGeometry(nullptr), [&] {
    requireHandle(d);
    if (!isKnownGeometryType(type)) fail(RTC_ERROR_UNKNOWN, "invalid geometry type");
    if (type != RTC_GEOMETRY_TYPE_TRIANGLE && type != RTC_GEOMETRY_TYPE_QUAD)
      fail(RTC_ERROR_INVALID_OPERATION,
           "geometry type " + std::to_string(int(type)) + " is not supported by obvh yet (triangles and quads are)");
    return (new Geometry(d, type))->handle();
  });
}

RTC_API void rtcRetainGeometry(RTCGeometry geometry) { withGeometry(geometry, [](Geometry& g) { g.retain(); }); }
RTC_API void rtcReleaseGeometry(RTCGeometry geometry) { withGeometry(geometry, [](Geometry& g) { g.release(); }); }
RTC_API void rtcCommitGeometry(RTCGeometry geometry) { withGeometry(geometry, [](Geometry& g) { g.commit(); }); }
RTC_API void rtcEnableGeometry(RTCGeometry geometry) { withGeometry(geometry, [](Geometry& g) { g.setEnabled(true); }); }
RTC_API void rtcDisableGeometry(RTCGeometry geometry) { withGeometry(geometry, [](Geometry& g) { g.setEnabled(false); }); }

RTC_API void rtcSetGeometryTimeStepCount(RTCGeometry geometry, unsigned int timeStepCount) {
  withGeometry(geometry, [&](Geometry& g) { g.setTimeStepCount(timeStepCount); });
}

RTC_API void rtcSetGeometryTimeRange(RTCGeometry geometry, float startTime, float endTime) {
  withGeometry(geometry, [&](Geometry&) {
    if (startTime > endTime) fail(RTC_ERROR_INVALID_ARGUMENT, "startTime has to be smaller or equal to the endTime");
  });
}

RTC_API void rtcSetGeometryVertexAttributeCount(RTCGeometry geometry, unsigned int count) {
  withGeometry(geometry, [&](Geometry& g) { g.setVertexAttributeCount(count); });
}

RTC_API void rtcSetGeometryMask(RTCGeometry geometry, unsigned int mask) {
  withGeometry(geometry, [&](Geometry& g) { g.setMask(mask); });
}

RTC_API void rtcSetGeometryBuildQuality(RTCGeometry geometry, RTCBuildQuality quality) {
  withGeometry(geometry, [&](Geometry& g) { g.setBuildQuality(quality); });
}

RTC_API void rtcSetGeometryMaxRadiusScale(RTCGeometry geometry, float) { failForThisGeometry(geometry); }

RTC_API void rtcSetGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                  RTCBuffer buffer, size_t byteOffset, size_t byteStride, size_t itemCount) {
  withGeometry(geometry, [&](Geometry& g) {
    Buffer* b = requireHandle(Buffer::from(buffer));
    if (b->device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    g.setBuffer(type, slot, format, Ref<Buffer>(b), byteOffset, byteStride, itemCount);
  });
}

RTC_API void rtcSetSharedGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot,
                                        RTCFormat format, const void* ptr, size_t byteOffset, size_t byteStride,
                                        size_t itemCount) {
  withGeometry(geometry, [&](Geometry& g) {
    // The application promises itemCount items; the shared buffer spans exactly that range.
    const size_t byteSize = byteOffset + byteStride * itemCount;
    Ref<Buffer> shared(new Buffer(g.device(), const_cast<void*>(ptr), byteSize), true);
    g.setBuffer(type, slot, format, shared, byteOffset, byteStride, itemCount);
  });
}

RTC_API void* rtcSetNewGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                      size_t byteStride, size_t itemCount) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] {
    requireHandle(g);
    Ref<Buffer> owned(new Buffer(g->device(), byteStride * itemCount), true);
    g->setBuffer(type, slot, format, owned, 0, byteStride, itemCount);
    return static_cast<void*>(owned->data());
  });
}

RTC_API void* rtcGetGeometryBufferData(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] { return requireHandle(g)->bufferData(type, slot); });
}

RTC_API void rtcUpdateGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  withGeometry(geometry, [&](Geometry& g) { g.updateBuffer(type, slot); });
}

RTC_API void rtcSetGeometryUserData(RTCGeometry geometry, void* ptr) {
  withGeometry(geometry, [&](Geometry& g) { g.setUserData(ptr); });
}

RTC_API void* rtcGetGeometryUserData(RTCGeometry geometry) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] { return requireHandle(g)->userData(); });
}

// Callbacks and operations of later slices: they fail loudly instead of being silently ignored.
RTC_API void rtcSetGeometryIntersectFilterFunction(RTCGeometry geometry, RTCFilterFunctionN) {
  withGeometry(geometry, [](Geometry&) {
    fail(RTC_ERROR_INVALID_OPERATION, "intersection filter functions are not supported by obvh yet");
  });
}

RTC_API void rtcSetGeometryOccludedFilterFunction(RTCGeometry geometry, RTCFilterFunctionN) {
  withGeometry(geometry, [](Geometry&) {
    fail(RTC_ERROR_INVALID_OPERATION, "occlusion filter functions are not supported by obvh yet");
  });
}

RTC_API void rtcSetGeometryPointQueryFunction(RTCGeometry geometry, RTCPointQueryFunction) {
  withGeometry(geometry, [](Geometry&) {
    fail(RTC_ERROR_INVALID_OPERATION, "point queries are not supported by obvh yet");
  });
}

RTC_API void rtcSetGeometryUserPrimitiveCount(RTCGeometry geometry, unsigned int) {
  withGeometry(geometry, [](Geometry&) { fail(RTC_ERROR_INVALID_OPERATION, "operation only allowed for user geometries"); });
}
RTC_API void rtcSetGeometryBoundsFunction(RTCGeometry geometry, RTCBoundsFunction, void*) {
  withGeometry(geometry, [](Geometry&) { fail(RTC_ERROR_INVALID_OPERATION, "operation only allowed for user geometries"); });
}
RTC_API void rtcSetGeometryIntersectFunction(RTCGeometry geometry, RTCIntersectFunctionN) {
  withGeometry(geometry, [](Geometry&) { fail(RTC_ERROR_INVALID_OPERATION, "operation only allowed for user geometries"); });
}
RTC_API void rtcSetGeometryOccludedFunction(RTCGeometry geometry, RTCOccludedFunctionN) {
  withGeometry(geometry, [](Geometry&) { fail(RTC_ERROR_INVALID_OPERATION, "operation only allowed for user geometries"); });
}

RTC_API void rtcSetGeometryInstancedScene(RTCGeometry geometry, RTCScene) { failForThisGeometry(geometry); }
RTC_API void rtcSetGeometryTransform(RTCGeometry geometry, unsigned int, RTCFormat, const void*) {
  failForThisGeometry(geometry);
}
RTC_API void rtcSetGeometryTransformQuaternion(RTCGeometry geometry, unsigned int,
                                               const RTCQuaternionDecomposition*) {
  failForThisGeometry(geometry);
}
RTC_API void rtcGetGeometryTransform(RTCGeometry geometry, float, RTCFormat, void*) { failForThisGeometry(geometry); }
RTC_API void rtcSetGeometryTessellationRate(RTCGeometry geometry, float) { failForThisGeometry(geometry); }
RTC_API void rtcSetGeometryTopologyCount(RTCGeometry geometry, unsigned int) { failForThisGeometry(geometry); }
RTC_API void rtcSetGeometrySubdivisionMode(RTCGeometry geometry, unsigned int, RTCSubdivisionMode) {
  failForThisGeometry(geometry);
}
RTC_API void rtcSetGeometryVertexAttributeTopology(RTCGeometry geometry, unsigned int, unsigned int) {
  failForThisGeometry(geometry);
}
RTC_API void rtcSetGeometryDisplacementFunction(RTCGeometry geometry, RTCDisplacementFunctionN) {
  failForThisGeometry(geometry);
}

namespace {
unsigned failHalfEdge(RTCGeometry geometry) {
  failForThisGeometry(geometry);
  return RTC_INVALID_GEOMETRY_ID;
}
}  // namespace

RTC_API unsigned int rtcGetGeometryFirstHalfEdge(RTCGeometry geometry, unsigned int) { return failHalfEdge(geometry); }
RTC_API unsigned int rtcGetGeometryFace(RTCGeometry geometry, unsigned int) { return failHalfEdge(geometry); }
RTC_API unsigned int rtcGetGeometryNextHalfEdge(RTCGeometry geometry, unsigned int) { return failHalfEdge(geometry); }
RTC_API unsigned int rtcGetGeometryPreviousHalfEdge(RTCGeometry geometry, unsigned int) {
  return failHalfEdge(geometry);
}
RTC_API unsigned int rtcGetGeometryOppositeHalfEdge(RTCGeometry geometry, unsigned int, unsigned int) {
  return failHalfEdge(geometry);
}

RTC_API void rtcInterpolate(const RTCInterpolateArguments* args) {
  withGeometry(args ? args->geometry : nullptr, [](Geometry&) {
    fail(RTC_ERROR_INVALID_OPERATION, "rtcInterpolate is not supported by obvh yet");
  });
}

RTC_API void rtcInterpolateN(const RTCInterpolateNArguments* args) {
  withGeometry(args ? args->geometry : nullptr, [](Geometry&) {
    fail(RTC_ERROR_INVALID_OPERATION, "rtcInterpolateN is not supported by obvh yet");
  });
}

// These are called from inside user-geometry callbacks, which obvh does not run yet; there is no
// device to report on, so the error goes to the device-less error slot.
RTC_API void rtcFilterIntersection(const RTCIntersectFunctionNArguments*, const RTCFilterFunctionNArguments*) {
  reportError(nullptr, RTC_ERROR_INVALID_OPERATION, "rtcFilterIntersection is not supported by obvh yet");
}

RTC_API void rtcFilterOcclusion(const RTCOccludedFunctionNArguments*, const RTCFilterFunctionNArguments*) {
  reportError(nullptr, RTC_ERROR_INVALID_OPERATION, "rtcFilterOcclusion is not supported by obvh yet");
}
