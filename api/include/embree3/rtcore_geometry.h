// obvh: geometry objects, their buffers, callbacks and attribute interpolation.
#pragma once

#include "rtcore_buffer.h"
#include "rtcore_quaternion.h"

typedef struct RTCSceneTy* RTCScene;
typedef struct RTCGeometryTy* RTCGeometry;

enum RTCGeometryType
{
  RTC_GEOMETRY_TYPE_TRIANGLE = 0,
  RTC_GEOMETRY_TYPE_QUAD = 1,
  RTC_GEOMETRY_TYPE_GRID = 2,

  RTC_GEOMETRY_TYPE_SUBDIVISION = 8,

  RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE = 15,
  RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE = 16,
  RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE = 17,

  RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE = 24,
  RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE = 25,
  RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE = 26,

  RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE = 32,
  RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE = 33,
  RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE = 34,

  RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE = 40,
  RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE = 41,
  RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_HERMITE_CURVE = 42,

  RTC_GEOMETRY_TYPE_SPHERE_POINT = 50,
  RTC_GEOMETRY_TYPE_DISC_POINT = 51,
  RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT = 52,

  RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE = 58,
  RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE = 59,
  RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_CATMULL_ROM_CURVE = 60,

  RTC_GEOMETRY_TYPE_USER = 120,
  RTC_GEOMETRY_TYPE_INSTANCE = 121
};

enum RTCSubdivisionMode
{
  RTC_SUBDIVISION_MODE_NO_BOUNDARY = 0,
  RTC_SUBDIVISION_MODE_SMOOTH_BOUNDARY = 1,
  RTC_SUBDIVISION_MODE_PIN_CORNERS = 2,
  RTC_SUBDIVISION_MODE_PIN_BOUNDARY = 3,
  RTC_SUBDIVISION_MODE_PIN_ALL = 4,
};

enum RTCCurveFlags
{
  RTC_CURVE_FLAG_NEIGHBOR_LEFT = (1 << 0),
  RTC_CURVE_FLAG_NEIGHBOR_RIGHT = (1 << 1)
};

struct RTCBoundsFunctionArguments
{
  void* geometryUserPtr;
  unsigned int primID;
  unsigned int timeStep;
  struct RTCBounds* bounds_o;
};
typedef void (*RTCBoundsFunction)(const struct RTCBoundsFunctionArguments* args);

struct RTCIntersectFunctionNArguments
{
  int* valid;
  void* geometryUserPtr;
  unsigned int primID;
  struct RTCIntersectContext* context;
  struct RTCRayHitN* rayhit;
  unsigned int N;
  unsigned int geomID;
};
typedef void (*RTCIntersectFunctionN)(const struct RTCIntersectFunctionNArguments* args);

struct RTCOccludedFunctionNArguments
{
  int* valid;
  void* geometryUserPtr;
  unsigned int primID;
  struct RTCIntersectContext* context;
  struct RTCRayN* ray;
  unsigned int N;
  unsigned int geomID;
};
typedef void (*RTCOccludedFunctionN)(const struct RTCOccludedFunctionNArguments* args);

struct RTCDisplacementFunctionNArguments
{
  void* geometryUserPtr;
  RTCGeometry geometry;
  unsigned int primID;
  unsigned int timeStep;
  const float* u;
  const float* v;
  const float* Ng_x;
  const float* Ng_y;
  const float* Ng_z;
  float* P_x;
  float* P_y;
  float* P_z;
  unsigned int N;
};
typedef void (*RTCDisplacementFunctionN)(const struct RTCDisplacementFunctionNArguments* args);

RTC_API RTCGeometry rtcNewGeometry(RTCDevice device, enum RTCGeometryType type);
RTC_API void rtcRetainGeometry(RTCGeometry geometry);
RTC_API void rtcReleaseGeometry(RTCGeometry geometry);
RTC_API void rtcCommitGeometry(RTCGeometry geometry);
RTC_API void rtcEnableGeometry(RTCGeometry geometry);
RTC_API void rtcDisableGeometry(RTCGeometry geometry);

RTC_API void rtcSetGeometryTimeStepCount(RTCGeometry geometry, unsigned int timeStepCount);
RTC_API void rtcSetGeometryTimeRange(RTCGeometry geometry, float startTime, float endTime);
RTC_API void rtcSetGeometryVertexAttributeCount(RTCGeometry geometry, unsigned int vertexAttributeCount);
RTC_API void rtcSetGeometryMask(RTCGeometry geometry, unsigned int mask);
RTC_API void rtcSetGeometryBuildQuality(RTCGeometry geometry, enum RTCBuildQuality quality);
RTC_API void rtcSetGeometryMaxRadiusScale(RTCGeometry geometry, float maxRadiusScale);

RTC_API void rtcSetGeometryBuffer(RTCGeometry geometry, enum RTCBufferType type, unsigned int slot,
                                  enum RTCFormat format, RTCBuffer buffer, size_t byteOffset,
                                  size_t byteStride, size_t itemCount);
RTC_API void rtcSetSharedGeometryBuffer(RTCGeometry geometry, enum RTCBufferType type, unsigned int slot,
                                        enum RTCFormat format, const void* ptr, size_t byteOffset,
                                        size_t byteStride, size_t itemCount);
RTC_API void* rtcSetNewGeometryBuffer(RTCGeometry geometry, enum RTCBufferType type, unsigned int slot,
                                      enum RTCFormat format, size_t byteStride, size_t itemCount);
RTC_API void* rtcGetGeometryBufferData(RTCGeometry geometry, enum RTCBufferType type, unsigned int slot);
RTC_API void rtcUpdateGeometryBuffer(RTCGeometry geometry, enum RTCBufferType type, unsigned int slot);

RTC_API void rtcSetGeometryIntersectFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter);
RTC_API void rtcSetGeometryOccludedFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter);
RTC_API void rtcSetGeometryUserData(RTCGeometry geometry, void* ptr);
RTC_API void* rtcGetGeometryUserData(RTCGeometry geometry);
RTC_API void rtcSetGeometryPointQueryFunction(RTCGeometry geometry, RTCPointQueryFunction pointQuery);

RTC_API void rtcSetGeometryUserPrimitiveCount(RTCGeometry geometry, unsigned int userPrimitiveCount);
RTC_API void rtcSetGeometryBoundsFunction(RTCGeometry geometry, RTCBoundsFunction bounds, void* userPtr);
RTC_API void rtcSetGeometryIntersectFunction(RTCGeometry geometry, RTCIntersectFunctionN intersect);
RTC_API void rtcSetGeometryOccludedFunction(RTCGeometry geometry, RTCOccludedFunctionN occluded);
RTC_API void rtcFilterIntersection(const struct RTCIntersectFunctionNArguments* args,
                                   const struct RTCFilterFunctionNArguments* filterArgs);
RTC_API void rtcFilterOcclusion(const struct RTCOccludedFunctionNArguments* args,
                                const struct RTCFilterFunctionNArguments* filterArgs);

RTC_API void rtcSetGeometryInstancedScene(RTCGeometry geometry, RTCScene scene);
RTC_API void rtcSetGeometryTransform(RTCGeometry geometry, unsigned int timeStep, enum RTCFormat format,
                                     const void* xfm);
RTC_API void rtcSetGeometryTransformQuaternion(RTCGeometry geometry, unsigned int timeStep,
                                               const struct RTCQuaternionDecomposition* qd);
RTC_API void rtcGetGeometryTransform(RTCGeometry geometry, float time, enum RTCFormat format, void* xfm);

RTC_API void rtcSetGeometryTessellationRate(RTCGeometry geometry, float tessellationRate);
RTC_API void rtcSetGeometryTopologyCount(RTCGeometry geometry, unsigned int topologyCount);
RTC_API void rtcSetGeometrySubdivisionMode(RTCGeometry geometry, unsigned int topologyID,
                                           enum RTCSubdivisionMode mode);
RTC_API void rtcSetGeometryVertexAttributeTopology(RTCGeometry geometry, unsigned int vertexAttributeID,
                                                   unsigned int topologyID);
RTC_API void rtcSetGeometryDisplacementFunction(RTCGeometry geometry, RTCDisplacementFunctionN displacement);
RTC_API unsigned int rtcGetGeometryFirstHalfEdge(RTCGeometry geometry, unsigned int faceID);
RTC_API unsigned int rtcGetGeometryFace(RTCGeometry geometry, unsigned int edgeID);
RTC_API unsigned int rtcGetGeometryNextHalfEdge(RTCGeometry geometry, unsigned int edgeID);
RTC_API unsigned int rtcGetGeometryPreviousHalfEdge(RTCGeometry geometry, unsigned int edgeID);
RTC_API unsigned int rtcGetGeometryOppositeHalfEdge(RTCGeometry geometry, unsigned int topologyID,
                                                    unsigned int edgeID);

struct RTCInterpolateArguments
{
  RTCGeometry geometry;
  unsigned int primID;
  float u;
  float v;
  enum RTCBufferType bufferType;
  unsigned int bufferSlot;
  float* P;
  float* dPdu;
  float* dPdv;
  float* ddPdudu;
  float* ddPdvdv;
  float* ddPdudv;
  unsigned int valueCount;
};

RTC_API void rtcInterpolate(const struct RTCInterpolateArguments* args);

RTC_FORCEINLINE void rtcInterpolate2(RTCGeometry geometry, unsigned int primID, float u, float v,
                                     enum RTCBufferType bufferType, unsigned int bufferSlot, float* P,
                                     float* dPdu, float* dPdv, float* ddPdudu, float* ddPdvdv,
                                     float* ddPdudv, unsigned int valueCount)
{
  struct RTCInterpolateArguments args;
  args.geometry = geometry;
  args.primID = primID;
  args.u = u;
  args.v = v;
  args.bufferType = bufferType;
  args.bufferSlot = bufferSlot;
  args.P = P;
  args.dPdu = dPdu;
  args.dPdv = dPdv;
  args.ddPdudu = ddPdudu;
  args.ddPdvdv = ddPdvdv;
  args.ddPdudv = ddPdudv;
  args.valueCount = valueCount;
  rtcInterpolate(&args);
}

// Value and first derivatives only.
RTC_FORCEINLINE void rtcInterpolate1(RTCGeometry geometry, unsigned int primID, float u, float v,
                                     enum RTCBufferType bufferType, unsigned int bufferSlot, float* P,
                                     float* dPdu, float* dPdv, unsigned int valueCount)
{
  rtcInterpolate2(geometry, primID, u, v, bufferType, bufferSlot, P, dPdu, dPdv, NULL, NULL, NULL, valueCount);
}

// Value only.
RTC_FORCEINLINE void rtcInterpolate0(RTCGeometry geometry, unsigned int primID, float u, float v,
                                     enum RTCBufferType bufferType, unsigned int bufferSlot, float* P,
                                     unsigned int valueCount)
{
  rtcInterpolate2(geometry, primID, u, v, bufferType, bufferSlot, P, NULL, NULL, NULL, NULL, NULL, valueCount);
}

struct RTCInterpolateNArguments
{
  RTCGeometry geometry;
  const void* valid;
  const unsigned int* primIDs;
  const float* u;
  const float* v;
  unsigned int N;
  enum RTCBufferType bufferType;
  unsigned int bufferSlot;
  float* P;
  float* dPdu;
  float* dPdv;
  float* ddPdudu;
  float* ddPdvdv;
  float* ddPdudv;
  unsigned int valueCount;
};

RTC_API void rtcInterpolateN(const struct RTCInterpolateNArguments* args);

struct RTCGrid
{
  unsigned int startVertexID;
  unsigned int stride;
  unsigned short width, height;
};
