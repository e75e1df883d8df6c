#include "geometry.h"

#include <algorithm>
#include <cstring>

#include "api_error.h"
#include "scene.h"

namespace obvh::api {

Geometry::Geometry(Device* device, RTCGeometryType type)
    : device_(device), type_(type), vertices_(1), tangents_(isHermiteType(type) ? 1 : 0) {
  if (type == RTC_GEOMETRY_TYPE_SUBDIVISION) subdivision_ = std::make_unique<SubdivisionGeometry>();
}

SubdivisionGeometry& Geometry::subdivision() {
  if (!subdivision_) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  return *subdivision_;
}

const SubdivisionGeometry& Geometry::subdivision() const {
  if (!subdivision_) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  return *subdivision_;
}

Geometry::~Geometry() {
  if (instancedScene_) instancedScene_->release();
}

namespace {

void requireType(const Geometry& g, RTCGeometryType type, const char* message) {
  if (g.type() != type) fail(RTC_ERROR_INVALID_OPERATION, message);
}

}  // namespace

void Geometry::setInstancedScene(Scene* scene) {
  requireType(*this, RTC_GEOMETRY_TYPE_INSTANCE, "operation not supported for this geometry");
  if (scene) scene->retain();
  if (instancedScene_) instancedScene_->release();
  instancedScene_ = scene;
  markModified();
}

void Geometry::setTransform(unsigned timeStep, const Affine3f& xfm) {
  requireType(*this, RTC_GEOMETRY_TYPE_INSTANCE, "operation not supported for this geometry");
  if (timeStep >= transforms_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid timestep");
  transforms_[timeStep] = {xfm, {}, false};
  markModified();
}

void Geometry::setTransform(unsigned timeStep, const QuaternionDecomposition& decomposition) {
  Affine3f m;
  if (!decomposition.compose(m)) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid quaternion");
  setTransform(timeStep, m);
  transforms_[timeStep] = {m, decomposition, true};
}

InstanceMotion Geometry::instanceMotion() const {
  InstanceMotion motion;
  if (transforms_.size() < 2) return motion;
  for (const TimeStepTransform& step : transforms_) motion.steps.push_back(step.transform);
  // Quaternion interpolation when every step was given as a decomposition.
  if (std::all_of(transforms_.begin(), transforms_.end(), [](const TimeStepTransform& s) { return s.givenAsDecomposition; }))
    for (const TimeStepTransform& step : transforms_) motion.quaternions.push_back(step.decomposition);
  motion.timeStart = timeStart_, motion.timeEnd = timeEnd_;
  return motion;
}

void Geometry::setTransform(unsigned timeStep, int format, const void* xfm) {
  if (!xfm) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null transform");
  const float* m = static_cast<const float*>(xfm);
  Affine3f a;
  switch (format) {
    case RTC_FORMAT_FLOAT3X4_ROW_MAJOR:  // rows: (vx.x vy.x vz.x p.x) ...
      a.vx = {m[0], m[4], m[8]}, a.vy = {m[1], m[5], m[9]}, a.vz = {m[2], m[6], m[10]}, a.p = {m[3], m[7], m[11]};
      break;
    case RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR:
      a.vx = {m[0], m[1], m[2]}, a.vy = {m[3], m[4], m[5]}, a.vz = {m[6], m[7], m[8]}, a.p = {m[9], m[10], m[11]};
      break;
    case RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR:
      a.vx = {m[0], m[1], m[2]}, a.vy = {m[4], m[5], m[6]}, a.vz = {m[8], m[9], m[10]}, a.p = {m[12], m[13], m[14]};
      break;
    default:
      fail(RTC_ERROR_INVALID_OPERATION, "invalid matrix format");
  }
  setTransform(timeStep, a);
}

void Geometry::getTransform(float time, int format, void* xfm) const {
  requireType(*this, RTC_GEOMETRY_TYPE_INSTANCE, "operation not supported for this geometry");
  if (!xfm) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null transform");
  float* m = static_cast<float*>(xfm);
  Affine3f a = transforms_[0].transform;
  // A moving instance's transform at that time (clamped to its time range).
  const InstanceMotion motion = instanceMotion();
  if (motion.moving()) motion.at(std::clamp(time, timeStart_, timeEnd_), a);
  switch (format) {
    case RTC_FORMAT_FLOAT3X4_ROW_MAJOR: {
      const float r[12] = {a.vx.x, a.vy.x, a.vz.x, a.p.x, a.vx.y, a.vy.y, a.vz.y, a.p.y, a.vx.z, a.vy.z, a.vz.z, a.p.z};
      std::memcpy(m, r, sizeof r);
      break;
    }
    case RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR: {
      const float c[12] = {a.vx.x, a.vx.y, a.vx.z, a.vy.x, a.vy.y, a.vy.z, a.vz.x, a.vz.y, a.vz.z, a.p.x, a.p.y, a.p.z};
      std::memcpy(m, c, sizeof c);
      break;
    }
    case RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR: {
      const float c[16] = {a.vx.x, a.vx.y, a.vx.z, 0.f, a.vy.x, a.vy.y, a.vy.z, 0.f,
                           a.vz.x, a.vz.y, a.vz.z, 0.f, a.p.x,  a.p.y,  a.p.z,  1.f};
      std::memcpy(m, c, sizeof c);
      break;
    }
    default:
      fail(RTC_ERROR_INVALID_OPERATION, "invalid matrix format");
  }
}

void Geometry::setUserPrimitiveCount(unsigned count) {
  requireType(*this, RTC_GEOMETRY_TYPE_USER, "operation only allowed for user geometries");
  user_.primitiveCount = count;
  markModified();
}

void Geometry::setBoundsFunction(RTCBoundsFunction fn, void* userPtr) {
  requireType(*this, RTC_GEOMETRY_TYPE_USER, "operation only allowed for user geometries");
  user_.bounds = fn;
  user_.boundsUserPtr = userPtr;
  ++modCounter_;
}

void Geometry::setIntersectFunction(RTCIntersectFunctionN fn) {
  requireType(*this, RTC_GEOMETRY_TYPE_USER, "operation only allowed for user geometries");
  user_.intersect = fn;
  ++modCounter_;
}

void Geometry::setOccludedFunction(RTCOccludedFunctionN fn) {
  requireType(*this, RTC_GEOMETRY_TYPE_USER, "operation only allowed for user geometries");
  user_.occluded = fn;
  ++modCounter_;
}

const BufferView& Geometry::attributeBuffer(unsigned slot) const {
  if (slot >= attributes_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
  return attributes_[slot];
}

BufferView& Geometry::view(int type, unsigned slot) {
  if (isSubdivision() && SubdivisionGeometry::ownsBufferType(type)) return subdivision_->view(type, slot);
  // A grid mesh has a grid buffer where the other meshes have an index buffer.
  const int primitiveBufferType = isGridMesh() ? RTC_BUFFER_TYPE_GRID : RTC_BUFFER_TYPE_INDEX;
  if (type == RTC_BUFFER_TYPE_INDEX || type == RTC_BUFFER_TYPE_GRID) {
    if (type != primitiveBufferType) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
    if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
    return index_;
  }
  switch (type) {
    case RTC_BUFFER_TYPE_VERTEX:
      if (slot >= vertices_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return vertices_[slot];
    case RTC_BUFFER_TYPE_FLAGS:
      if (!isCurve()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return flags_;
    case RTC_BUFFER_TYPE_TANGENT:
      if (!isHermite()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      if (slot >= tangents_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return tangents_[slot];
    case RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE:
      if (slot >= attributes_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return attributes_[slot];
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
}

void Geometry::setBuffer(int type, unsigned slot, int format, const Ref<Buffer>& buffer,
                         size_t byteOffset, size_t byteStride, size_t itemCount, bool checkRange) {
  if (!isMesh() && !isShape() && !isSubdivision()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  // Checked first, as Embree does; flags (curves) are bytes.
  const uintptr_t start = reinterpret_cast<uintptr_t>(buffer->data()) + byteOffset;
  const bool bytes = type == RTC_BUFFER_TYPE_FLAGS && isShape();
  if (!bytes && ((start & 3u) != 0 || (byteStride & 3u) != 0))
    fail(RTC_ERROR_INVALID_OPERATION, "data must be 4 bytes aligned");
  if (isSubdivision() && SubdivisionGeometry::ownsBufferType(type)) {
    subdivision_->checkBinding(type, slot, format);
  } else switch (type) {
    case RTC_BUFFER_TYPE_GRID:
      if (!isGridMesh()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      if (format != RTC_FORMAT_GRID) fail(RTC_ERROR_INVALID_OPERATION, "invalid grid buffer format");
      break;
    case RTC_BUFFER_TYPE_INDEX: {
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      if (type_ == RTC_GEOMETRY_TYPE_SPHERE_POINT || isGridMesh()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      const int indexFormat = isQuadMesh() ? RTC_FORMAT_UINT4 : isShape() ? RTC_FORMAT_UINT : RTC_FORMAT_UINT3;
      if (format != indexFormat) fail(RTC_ERROR_INVALID_OPERATION, "invalid index buffer format");
      break;
    }
    case RTC_BUFFER_TYPE_VERTEX:
      if (slot >= vertices_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid vertex buffer slot");
      if (format != (isShape() ? RTC_FORMAT_FLOAT4 : RTC_FORMAT_FLOAT3))
        fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex buffer format");
      break;
    case RTC_BUFFER_TYPE_FLAGS:
      if (!isCurve()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      if (format != RTC_FORMAT_UCHAR) fail(RTC_ERROR_INVALID_OPERATION, "invalid flags buffer format");
      break;
    case RTC_BUFFER_TYPE_TANGENT:
      if (!isHermite()) fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
      if (slot >= tangents_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid tangent buffer slot");
      if (format != RTC_FORMAT_FLOAT4) fail(RTC_ERROR_INVALID_OPERATION, "invalid tangent buffer format");
      break;
    case RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE:
      if (slot >= attributes_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer slot");
      if (formatByteSize(format) == 0) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer format");
      break;
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
  // Embree does not check this; obvh does, because reading past the buffer could crash.
  if (checkRange && itemCount > 0 && byteOffset + (itemCount - 1) * byteStride + formatByteSize(format) > buffer->size())
    fail(RTC_ERROR_INVALID_ARGUMENT, "buffer range out of bounds");
  if (itemCount > 0xFFFFFFFFu) fail(RTC_ERROR_INVALID_ARGUMENT, "buffer too large");

  BufferView& target = view(type, slot);
  target = BufferView{buffer, byteOffset, byteStride, itemCount, format};
  markModified();
}

obvh::ShapeKind Geometry::shapeKind() const {
  using obvh::ShapeKind;
  switch (type_) {
    case RTC_GEOMETRY_TYPE_SPHERE_POINT: return ShapeKind::Sphere;
    case RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE: return ShapeKind::FlatLinearCurve;
    case RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE: case RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE:
      return ShapeKind::RoundBezierCurve;
    case RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE: return ShapeKind::RoundBSplineCurve;
    case RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE: case RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE:
      return ShapeKind::FlatBezierCurve;
    case RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE: return ShapeKind::FlatBSplineCurve;
    case RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE: return ShapeKind::FlatCatmullRomCurve;
    default: return ShapeKind::RoundCatmullRomCurve;
  }
}

void Geometry::setTessellationRate(float rate) {
  if (!isCurve() && !isSubdivision()) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  if (isSubdivision()) subdivision_->setTessellationRate(rate);
  tessellationRate_ = rate;
  markModified();
}

void* Geometry::bufferData(int type, unsigned slot) { return view(type, slot).data(); }

void Geometry::updateBuffer(int type, unsigned slot) {
  view(type, slot);
  markModified();
}

void Geometry::setTimeStepCount(unsigned count) {
  if (count > RTC_MAX_TIME_STEP_COUNT) fail(RTC_ERROR_INVALID_ARGUMENT, "number of time steps is out of range");
  if (count == 0) return;  // Embree accepts 0 without an error; obvh keeps the steps it has
  const bool instance = type_ == RTC_GEOMETRY_TYPE_INSTANCE;
  if (count > 1 && !isMesh() && !isShape() && !isSubdivision() && !instance && type_ != RTC_GEOMETRY_TYPE_USER)
    fail(RTC_ERROR_INVALID_OPERATION, "motion blur is not supported by obvh for this geometry type");
  if (instance) {
    transforms_.resize(count);
  } else {
    vertices_.resize(count);
    if (isHermite()) tangents_.resize(count);
  }
  markModified();
}

void Geometry::setTimeRange(float start, float end) {
  if (start > end) fail(RTC_ERROR_INVALID_ARGUMENT, "startTime has to be smaller or equal to the endTime");
  timeStart_ = start, timeEnd_ = end;
  markModified();
}

void Geometry::setVertexAttributeCount(unsigned count) {
  attributes_.resize(count);
  markModified();
}

void Geometry::setSubdivisionMode(unsigned topology, int mode) {
  subdivision().setMode(topology, mode);
  markModified();
}

void Geometry::setVertexAttributeTopology(unsigned attribute, unsigned topology) {
  subdivision().setAttributeTopology(attribute, topology, vertexAttributeCount());
  markModified();
}

void Geometry::setMask(unsigned mask) {
  mask_ = mask;
  markModified();
}

void Geometry::setBuildQuality(int quality) {
  if (quality != RTC_BUILD_QUALITY_LOW && quality != RTC_BUILD_QUALITY_MEDIUM &&
      quality != RTC_BUILD_QUALITY_HIGH && quality != RTC_BUILD_QUALITY_REFIT)
    fail(RTC_ERROR_UNKNOWN, "invalid build quality");
  quality_ = quality;
  markModified();
}

void Geometry::setEnabled(bool enabled) {
  if (enabled_ == enabled) return;
  enabled_ = enabled;
  ++modCounter_;
}

void Geometry::commit() {
  for (const BufferView& step : vertices_)
    if (step.byteStride != vertices_[0].byteStride)
      fail(RTC_ERROR_INVALID_OPERATION, "stride of vertex buffers have to be identical for each time step");
  if (isSubdivision()) subdivision_->commit(vertices_);
  committed_ = true;
  ++modCounter_;
}

void Geometry::markModified() {
  committed_ = false;
  ++modCounter_;
}

}  // namespace obvh::api
