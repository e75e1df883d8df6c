// RTCGeometry: type, buffers, state and per-geometry settings.
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "buffer.h"
#include "device.h"
#include "math/affine.h"
#include "scene/instance_motion.h"
#include "scene/scene_desc.h"
#include "ref_counted.h"
#include "subdivision_geometry.h"

namespace obvh::api {

class Scene;

// Embree's user-geometry callbacks.
struct UserCallbacks {
  unsigned primitiveCount = 0;
  RTCBoundsFunction bounds = nullptr;
  void* boundsUserPtr = nullptr;
  RTCIntersectFunctionN intersect = nullptr;
  RTCOccludedFunctionN occluded = nullptr;
};

class Geometry : public RefCounted {
 public:
  Geometry(Device* device, RTCGeometryType type);
  ~Geometry() override;

  Device* device() const { return device_.get(); }
  RTCGeometryType type() const { return type_; }

  // checkRange: the buffer's size is known (rtcSetGeometryBuffer, rtcSetNewGeometryBuffer), so a
  // range past its end is rejected; shared pointers carry no size to check against.
  // Buffer types, formats and qualities arrive as raw bits (enum_bits.h): any value may be passed.
  void setBuffer(int type, unsigned slot, int format, const Ref<Buffer>& buffer,
                 size_t byteOffset, size_t byteStride, size_t itemCount, bool checkRange = true);
  // nullptr when nothing is bound; throws for a type or slot the geometry does not have.
  void* bufferData(int type, unsigned slot);
  void updateBuffer(int type, unsigned slot);

  // Motion blur: meshes take one vertex buffer per time step (vertexBuffer(step)) and instances one
  // transform, spread over the time range; other types have one time step.
  void setTimeStepCount(unsigned count);
  unsigned timeStepCount() const {
    return unsigned(type_ == RTC_GEOMETRY_TYPE_INSTANCE ? transforms_.size() : vertices_.size());
  }
  void setTimeRange(float start, float end);
  float timeStart() const { return timeStart_; }
  float timeEnd() const { return timeEnd_; }
  void setVertexAttributeCount(unsigned count);
  unsigned vertexAttributeCount() const { return unsigned(attributes_.size()); }
  void setSubdivisionMode(unsigned topology, int mode);
  void setVertexAttributeTopology(unsigned attribute, unsigned topology);
  void setMask(unsigned mask);
  void setBuildQuality(int quality);
  int buildQuality() const { return quality_; }
  void setEnabled(bool enabled);
  void commit();

  // Instances.
  void setInstancedScene(Scene* scene);
  Scene* instancedScene() const { return instancedScene_; }
  void setTransform(unsigned timeStep, int format, const void* xfm);
  void setTransform(unsigned timeStep, const Affine3f& xfm);
  void setTransform(unsigned timeStep, const QuaternionDecomposition& decomposition);
  const Affine3f& transform() const { return transforms_[0].transform; }
  // The transforms of every time step, for a moving instance.
  InstanceMotion instanceMotion() const;
  void getTransform(float time, int format, void* xfm) const;

  // User geometry.
  void setUserPrimitiveCount(unsigned count);
  void setBoundsFunction(RTCBoundsFunction fn, void* userPtr);
  void setIntersectFunction(RTCIntersectFunctionN fn);
  void setOccludedFunction(RTCOccludedFunctionN fn);
  const UserCallbacks& user() const { return user_; }

  // Filters (any geometry type).
  // Callbacks do not need a geometry commit (as in Embree); a scene commit picks them up.
  void setIntersectFilter(RTCFilterFunctionN fn) { intersectFilter_ = fn; ++modCounter_; }
  void setOccludedFilter(RTCFilterFunctionN fn) { occludedFilter_ = fn; ++modCounter_; }
  RTCFilterFunctionN intersectFilter() const { return intersectFilter_; }
  RTCFilterFunctionN occludedFilter() const { return occludedFilter_; }
  void setPointQueryFunction(RTCPointQueryFunction fn) { pointQuery_ = fn; }
  RTCPointQueryFunction pointQueryFunction() const { return pointQuery_; }

  void setUserData(void* ptr) { userData_ = ptr; }
  void* userData() const { return userData_; }

  bool enabled() const { return enabled_; }
  bool committed() const { return committed_; }
  unsigned mask() const { return mask_; }
  // Changes whenever something a scene build depends on changes.
  uint64_t modificationCounter() const { return modCounter_.load(); }
  const BufferView& indexBuffer() const { return index_; }
  const BufferView& vertexBuffer(unsigned timeStep = 0) const { return vertices_.at(timeStep); }
  bool isQuadMesh() const { return type_ == RTC_GEOMETRY_TYPE_QUAD; }
  bool isSubdivision() const { return type_ == RTC_GEOMETRY_TYPE_SUBDIVISION; }
  // Subdivision geometries' own buffers, settings and committed control meshes; throws
  // RTC_ERROR_INVALID_OPERATION on other types, as Embree answers subdivision calls there.
  SubdivisionGeometry& subdivision();
  const SubdivisionGeometry& subdivision() const;
  bool isGridMesh() const { return type_ == RTC_GEOMETRY_TYPE_GRID; }
  // Float3 vertices and a primitive buffer: indices (triangles, quads) or RTCGrid records (grids,
  // whose buffer indexBuffer() returns too).
  bool isMesh() const {
    return type_ == RTC_GEOMETRY_TYPE_TRIANGLE || type_ == RTC_GEOMETRY_TYPE_QUAD || type_ == RTC_GEOMETRY_TYPE_GRID;
  }
  // Sphere points, flat linear curves, round and flat cubic curves: float4 vertices (position and
  // radius).
  static bool isShapeType(int type) {
    return type == RTC_GEOMETRY_TYPE_SPHERE_POINT || type == RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE ||
           type == RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE || type == RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE ||
           type == RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE || type == RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE ||
           type == RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE || type == RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE ||
           isHermiteType(type);
  }
  // Hermite curves: a segment runs between vertices i and i + 1 with the tangents (float4: the
  // position's and the radius' derivative) of a tangent buffer per time step.
  static bool isHermiteType(int type) {
    return type == RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE || type == RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE;
  }
  bool isHermite() const { return isHermiteType(type_); }
  const BufferView& tangentBuffer(unsigned timeStep = 0) const { return tangents_.at(timeStep); }
  bool isShape() const { return isShapeType(type_); }
  // What the backend traces a shape geometry as (Hermite curves: as the Bezier curves they make).
  obvh::ShapeKind shapeKind() const;
  bool isCurve() const { return isShape() && type_ != RTC_GEOMETRY_TYPE_SPHERE_POINT; }
  // Curves: Embree takes a tessellation rate and a flags buffer for every curve type, but only flat
  // cubic curves (tessellation) and round linear curves (flags) read them. The flags buffer is
  // kept (the application may read it back; obvh has no round linear curves yet), the rate is what
  // flat cubic curves are cut into (Embree's default 4). Subdivision geometries take the rate as
  // the segments along every edge without a level buffer (default 2).
  void setTessellationRate(float rate);
  float tessellationRate() const { return tessellationRate_; }
  // Vertex attribute view for interpolation; throws for a slot the geometry does not have.
  const BufferView& attributeBuffer(unsigned slot) const;

  static Geometry* from(RTCGeometry handle) { return reinterpret_cast<Geometry*>(handle); }
  RTCGeometry handle() { return reinterpret_cast<RTCGeometry>(this); }

 private:
  BufferView& view(int type, unsigned slot);
  void markModified();

  Ref<Device> device_;
  RTCGeometryType type_;
  BufferView index_;  // the index buffer, or a grid mesh's grid buffer
  std::vector<BufferView> vertices_;  // per time step (user geometry: one empty view per step)
  std::vector<BufferView> attributes_;
  std::vector<BufferView> tangents_;  // Hermite curves, per time step
  BufferView flags_;  // curves
  std::unique_ptr<SubdivisionGeometry> subdivision_;
  unsigned mask_ = 0xFFFFFFFFu;
  float tessellationRate_ = 4.f;
  int quality_ = RTC_BUILD_QUALITY_MEDIUM;
  bool enabled_ = true;
  bool committed_ = false;
  void* userData_ = nullptr;
  std::atomic<uint64_t> modCounter_{0};
  Scene* instancedScene_ = nullptr;  // retained while set
  // An instance's transform at one time step, and its decomposition when it was given as one.
  struct TimeStepTransform {
    Affine3f transform;
    QuaternionDecomposition decomposition;
    bool givenAsDecomposition = false;
  };
  std::vector<TimeStepTransform> transforms_{TimeStepTransform{}};
  float timeStart_ = 0.f, timeEnd_ = 1.f;
  UserCallbacks user_;
  RTCFilterFunctionN intersectFilter_ = nullptr;
  RTCFilterFunctionN occludedFilter_ = nullptr;
  RTCPointQueryFunction pointQuery_ = nullptr;
};

}  // namespace obvh::api
