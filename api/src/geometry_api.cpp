// rtc* entry points for geometries.
#include <embree3/rtcore.h>

#include <cmath>
#include <string>

#include "api_error.h"
#include "enum_bits.h"
#include "geometry.h"
#include "scene.h"

using namespace obvh::api;

namespace {

Device* deviceOf(Geometry* g) { return g ? g->device() : nullptr; }

bool isKnownGeometryType(int type) {
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

RTC_API RTCGeometry rtcNewGeometry(RTCDevice device, RTCGeometryType typeArgument) {
  Device* d = Device::from(device);
  return guarded(d, RTCGeometry(nullptr), [&] {
    requireHandle(d);
    const int type = enumBits(typeArgument);
    if (!isKnownGeometryType(type)) fail(RTC_ERROR_UNKNOWN, "invalid geometry type");
    const bool implemented = type == RTC_GEOMETRY_TYPE_TRIANGLE || type == RTC_GEOMETRY_TYPE_QUAD ||
                             type == RTC_GEOMETRY_TYPE_GRID || type == RTC_GEOMETRY_TYPE_USER ||
                             type == RTC_GEOMETRY_TYPE_INSTANCE || type == RTC_GEOMETRY_TYPE_SUBDIVISION ||
                             Geometry::isShapeType(type);
    if (!implemented)
      fail(RTC_ERROR_INVALID_OPERATION, "geometry type " + std::to_string(int(type)) +
                                            " is not supported by obvh yet (triangles, quads, grids, user geometry, "
                                            "instances, sphere points, flat linear curves, and round and flat "
                                            "Bezier, B-spline and Catmull-Rom curves are)");
    return (new Geometry(d, static_cast<RTCGeometryType>(type)))->handle();  // validated above
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
  withGeometry(geometry, [&](Geometry& g) { g.setTimeRange(startTime, endTime); });
}

RTC_API void rtcSetGeometryVertexAttributeCount(RTCGeometry geometry, unsigned int count) {
  withGeometry(geometry, [&](Geometry& g) { g.setVertexAttributeCount(count); });
}

RTC_API void rtcSetGeometryMask(RTCGeometry geometry, unsigned int mask) {
  withGeometry(geometry, [&](Geometry& g) { g.setMask(mask); });
}

RTC_API void rtcSetGeometryBuildQuality(RTCGeometry geometry, RTCBuildQuality quality) {
  withGeometry(geometry, [&](Geometry& g) { g.setBuildQuality(enumBits(quality)); });
}

RTC_API void rtcSetGeometryMaxRadiusScale(RTCGeometry geometry, float) { failForThisGeometry(geometry); }

RTC_API void rtcSetGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                  RTCBuffer buffer, size_t byteOffset, size_t byteStride, size_t itemCount) {
  withGeometry(geometry, [&](Geometry& g) {
    Buffer* b = requireHandle(Buffer::from(buffer));
    if (b->device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    g.setBuffer(enumBits(type), slot, enumBits(format), Ref<Buffer>(b), byteOffset, byteStride, itemCount);
  });
}

RTC_API void rtcSetSharedGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot,
                                        RTCFormat format, const void* ptr, size_t byteOffset, size_t byteStride,
                                        size_t itemCount) {
  withGeometry(geometry, [&](Geometry& g) {
    // The application promises itemCount items; the shared buffer spans exactly that range.
    const size_t byteSize = byteOffset + byteStride * itemCount;
    Ref<Buffer> shared(new Buffer(g.device(), const_cast<void*>(ptr), byteSize), true);
    g.setBuffer(enumBits(type), slot, enumBits(format), shared, byteOffset, byteStride, itemCount, false);
  });
}

RTC_API void* rtcSetNewGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                      size_t byteStride, size_t itemCount) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] {
    requireHandle(g);
    Ref<Buffer> owned(new Buffer(g->device(), byteStride * itemCount), true);
    g->setBuffer(enumBits(type), slot, enumBits(format), owned, 0, byteStride, itemCount);
    return static_cast<void*>(owned->data());
  });
}

RTC_API void* rtcGetGeometryBufferData(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] { return requireHandle(g)->bufferData(enumBits(type), slot); });
}

RTC_API void rtcUpdateGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  withGeometry(geometry, [&](Geometry& g) { g.updateBuffer(enumBits(type), slot); });
}

RTC_API void rtcSetGeometryUserData(RTCGeometry geometry, void* ptr) {
  withGeometry(geometry, [&](Geometry& g) { g.setUserData(ptr); });
}

RTC_API void* rtcGetGeometryUserData(RTCGeometry geometry) {
  Geometry* g = Geometry::from(geometry);
  return guarded(deviceOf(g), static_cast<void*>(nullptr), [&] { return requireHandle(g)->userData(); });
}

RTC_API void rtcSetGeometryIntersectFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter) {
  withGeometry(geometry, [&](Geometry& g) { g.setIntersectFilter(filter); });
}

RTC_API void rtcSetGeometryOccludedFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter) {
  withGeometry(geometry, [&](Geometry& g) { g.setOccludedFilter(filter); });
}

RTC_API void rtcSetGeometryPointQueryFunction(RTCGeometry geometry, RTCPointQueryFunction pointQuery) {
  withGeometry(geometry, [&](Geometry& g) { g.setPointQueryFunction(pointQuery); });
}

RTC_API void rtcSetGeometryUserPrimitiveCount(RTCGeometry geometry, unsigned int count) {
  withGeometry(geometry, [&](Geometry& g) { g.setUserPrimitiveCount(count); });
}

RTC_API void rtcSetGeometryBoundsFunction(RTCGeometry geometry, RTCBoundsFunction bounds, void* userPtr) {
  withGeometry(geometry, [&](Geometry& g) { g.setBoundsFunction(bounds, userPtr); });
}

RTC_API void rtcSetGeometryIntersectFunction(RTCGeometry geometry, RTCIntersectFunctionN intersect) {
  withGeometry(geometry, [&](Geometry& g) { g.setIntersectFunction(intersect); });
}

RTC_API void rtcSetGeometryOccludedFunction(RTCGeometry geometry, RTCOccludedFunctionN occluded) {
  withGeometry(geometry, [&](Geometry& g) { g.setOccludedFunction(occluded); });
}

RTC_API void rtcSetGeometryInstancedScene(RTCGeometry geometry, RTCScene scene) {
  withGeometry(geometry, [&](Geometry& g) { g.setInstancedScene(requireHandle(Scene::from(scene))); });
}

RTC_API void rtcSetGeometryTransform(RTCGeometry geometry, unsigned int timeStep, RTCFormat format, const void* xfm) {
  withGeometry(geometry, [&](Geometry& g) { g.setTransform(timeStep, enumBits(format), xfm); });
}

// Embree's decomposition: M = T * R * S, with S upper triangular (scale, skew) plus a shift,
// R the rotation of the (normalized) quaternion and T the translation.
RTC_API void rtcSetGeometryTransformQuaternion(RTCGeometry geometry, unsigned int timeStep,
                                               const RTCQuaternionDecomposition* qd) {
  withGeometry(geometry, [&](Geometry& g) {
    requireHandle(qd);
    obvh::QuaternionDecomposition d;
    d.scale = {qd->scale_x, qd->scale_y, qd->scale_z};
    d.skewXY = qd->skew_xy, d.skewXZ = qd->skew_xz, d.skewYZ = qd->skew_yz;
    d.shift = {qd->shift_x, qd->shift_y, qd->shift_z};
    d.translation = {qd->translation_x, qd->translation_y, qd->translation_z};
    d.r = qd->quaternion_r, d.i = qd->quaternion_i, d.j = qd->quaternion_j, d.k = qd->quaternion_k;
    g.setTransform(timeStep, d);
  });
}

RTC_API void rtcGetGeometryTransform(RTCGeometry geometry, float time, RTCFormat format, void* xfm) {
  withGeometry(geometry, [&](Geometry& g) { g.getTransform(time, enumBits(format), xfm); });
}

RTC_API void rtcSetGeometryTessellationRate(RTCGeometry geometry, float rate) {
  withGeometry(geometry, [&](Geometry& g) { g.setTessellationRate(rate); });
}
RTC_API void rtcSetGeometryTopologyCount(RTCGeometry geometry, unsigned int count) {
  withGeometry(geometry, [&](Geometry& g) { g.subdivision().setTopologyCount(count); });
}
RTC_API void rtcSetGeometrySubdivisionMode(RTCGeometry geometry, unsigned int topologyID, RTCSubdivisionMode mode) {
  withGeometry(geometry, [&](Geometry& g) { g.setSubdivisionMode(topologyID, enumBits(mode)); });
}
RTC_API void rtcSetGeometryVertexAttributeTopology(RTCGeometry geometry, unsigned int attributeID, unsigned int topologyID) {
  withGeometry(geometry, [&](Geometry& g) { g.setVertexAttributeTopology(attributeID, topologyID); });
}
RTC_API void rtcSetGeometryDisplacementFunction(RTCGeometry geometry, RTCDisplacementFunctionN) {
  failForThisGeometry(geometry);
}

namespace {

// Half-edge queries read the committed control mesh of a subdivision geometry. Embree asserts on
// an uncommitted geometry or an edge past the end; obvh reports RTC_ERROR_INVALID_ARGUMENT.
template <typename Query>
unsigned halfEdgeQuery(RTCGeometry geometry, unsigned topologyID, Query query) {
  Geometry* g = Geometry::from(geometry);
  return guarded(g ? g->device() : nullptr, unsigned(RTC_INVALID_GEOMETRY_ID), [&] {
    requireHandle(g);
    const obvh::SubdivTopology* topology = g->subdivision().topology(topologyID);
    if (!topology) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid topology (not committed, or without index buffer)");
    return unsigned(query(*topology));
  });
}

uint32_t checkedHalfEdge(const obvh::SubdivTopology& topology, unsigned edgeID) {
  if (edgeID >= topology.halfEdgeCount()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid half-edge ID");
  return edgeID;
}

}  // namespace

RTC_API unsigned int rtcGetGeometryFirstHalfEdge(RTCGeometry geometry, unsigned int faceID) {
  return halfEdgeQuery(geometry, 0, [&](const obvh::SubdivTopology& t) {
    if (faceID >= t.faceCount()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid face ID");
    return t.firstHalfEdge(faceID);
  });
}
RTC_API unsigned int rtcGetGeometryFace(RTCGeometry geometry, unsigned int edgeID) {
  return halfEdgeQuery(geometry, 0, [&](const obvh::SubdivTopology& t) { return t.faceOfEdge(checkedHalfEdge(t, edgeID)); });
}
RTC_API unsigned int rtcGetGeometryNextHalfEdge(RTCGeometry geometry, unsigned int edgeID) {
  return halfEdgeQuery(geometry, 0, [&](const obvh::SubdivTopology& t) { return t.next(checkedHalfEdge(t, edgeID)); });
}
RTC_API unsigned int rtcGetGeometryPreviousHalfEdge(RTCGeometry geometry, unsigned int edgeID) {
  return halfEdgeQuery(geometry, 0, [&](const obvh::SubdivTopology& t) { return t.previous(checkedHalfEdge(t, edgeID)); });
}
// A boundary half-edge is its own opposite (as Embree answers).
RTC_API unsigned int rtcGetGeometryOppositeHalfEdge(RTCGeometry geometry, unsigned int topologyID, unsigned int edgeID) {
  return halfEdgeQuery(geometry, topologyID, [&](const obvh::SubdivTopology& t) {
    const uint32_t opposite = t.opposite(checkedHalfEdge(t, edgeID));
    return opposite == obvh::SubdivTopology::kNone ? uint32_t(edgeID) : opposite;
  });
}

