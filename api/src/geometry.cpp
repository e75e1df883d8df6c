#include "geometry.h"

#include "api_error.h"

namespace obvh::api {

Geometry::Geometry(Device* device, RTCGeometryType type) : device_(device), type_(type), vertices_(1) {}

BufferView& Geometry::view(RTCBufferType type, unsigned slot) {
  switch (type) {
    case RTC_BUFFER_TYPE_INDEX:
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return index_;
    case RTC_BUFFER_TYPE_VERTEX:
      if (slot >= vertices_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return vertices_[slot];
    case RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE:
      if (slot >= attributes_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      return attributes_[slot];
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
}

void Geometry::setBuffer(RTCBufferType type, unsigned slot, RTCFormat format, const Ref<Buffer>& buffer,
                         size_t byteOffset, size_t byteStride, size_t itemCount) {
  switch (type) {
    case RTC_BUFFER_TYPE_INDEX:
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      if (format != (isQuadMesh() ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3))
        fail(RTC_ERROR_INVALID_OPERATION, "invalid index buffer format");
      break;
    case RTC_BUFFER_TYPE_VERTEX:
      if (slot >= vertices_.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid vertex buffer slot");
      if (format != RTC_FORMAT_FLOAT3) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex buffer format");
      break;
    case RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE:
      if (slot >= attributes_.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer slot");
      if (formatByteSize(format) == 0) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer format");
      break;
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
  const uintptr_t start = reinterpret_cast<uintptr_t>(buffer->data()) + byteOffset;
  if ((start & 3u) != 0 || (byteStride & 3u) != 0) fail(RTC_ERROR_INVALID_OPERATION, "data must be 4 bytes aligned");
  // Embree does not check this; obvh does, because reading past the buffer could crash.
  if (itemCount > 0 && byteOffset + (itemCount - 1) * byteStride + formatByteSize(format) > buffer->size())
    fail(RTC_ERROR_INVALID_ARGUMENT, "buffer range out of bounds");
  if (itemCount > 0xFFFFFFFFu) fail(RTC_ERROR_INVALID_ARGUMENT, "buffer too large");

  BufferView& target = view(type, slot);
  target = BufferView{buffer, byteOffset, byteStride, itemCount, format};
  markModified();
}

void* Geometry::bufferData(RTCBufferType type, unsigned slot) { return view(type, slot).data(); }

void Geometry::updateBuffer(RTCBufferType type, unsigned slot) {
  view(type, slot);
  markModified();
}

void Geometry::setTimeStepCount(unsigned count) {
  if (count > RTC_MAX_TIME_STEP_COUNT) fail(RTC_ERROR_INVALID_ARGUMENT, "number of time steps is out of range");
  if (count > 1) fail(RTC_ERROR_INVALID_OPERATION, "motion blur (more than one time step) is not supported by obvh yet");
  markModified();
}

void Geometry::setVertexAttributeCount(unsigned count) {
  attributes_.resize(count);
  markModified();
}

void Geometry::setMask(unsigned mask) {
  mask_ = mask;
  markModified();
}

void Geometry::setBuildQuality(RTCBuildQuality quality) {
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
  committed_ = true;
  ++modCounter_;
}

void Geometry::markModified() {
  committed_ = false;
  ++modCounter_;
}

}  // namespace obvh::api
