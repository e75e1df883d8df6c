// RTCGeometry: type, buffers, state and per-geometry settings (this slice: triangle and quad meshes).
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <cstdint>
#include <vector>

#include "buffer.h"
#include "device.h"
#include "ref_counted.h"

namespace obvh::api {

class Geometry : public RefCounted {
 public:
  Geometry(Device* device, RTCGeometryType type);

  Device* device() const { return device_.get(); }
  RTCGeometryType type() const { return type_; }

  void setBuffer(RTCBufferType type, unsigned slot, RTCFormat format, const Ref<Buffer>& buffer,
                 size_t byteOffset, size_t byteStride, size_t itemCount);
  // nullptr when nothing is bound; throws for a type or slot the geometry does not have.
  void* bufferData(RTCBufferType type, unsigned slot);
  void updateBuffer(RTCBufferType type, unsigned slot);

  void setTimeStepCount(unsigned count);
  void setVertexAttributeCount(unsigned count);
  void setMask(unsigned mask);
  void setBuildQuality(RTCBuildQuality quality);
  void setEnabled(bool enabled);
  void commit();

  void setUserData(void* ptr) { userData_ = ptr; }
  void* userData() const { return userData_; }

  bool enabled() const { return enabled_; }
  bool committed() const { return committed_; }
  unsigned mask() const { return mask_; }
  // Changes whenever something a scene build depends on changes.
  uint64_t modificationCounter() const { return modCounter_.load(); }
  const BufferView& indexBuffer() const { return index_; }
  const BufferView& vertexBuffer() const { return vertices_[0]; }
  bool isQuadMesh() const { return type_ == RTC_GEOMETRY_TYPE_QUAD; }

  static Geometry* from(RTCGeometry handle) { return reinterpret_cast<Geometry*>(handle); }
  RTCGeometry handle() { return reinterpret_cast<RTCGeometry>(this); }

 private:
  BufferView& view(RTCBufferType type, unsigned slot);
  void markModified();

  Ref<Device> device_;
  RTCGeometryType type_;
  BufferView index_;
  std::vector<BufferView> vertices_;
  std::vector<BufferView> attributes_;
  unsigned mask_ = 0xFFFFFFFFu;
  RTCBuildQuality quality_ = RTC_BUILD_QUALITY_MEDIUM;
  bool enabled_ = true;
  bool committed_ = false;
  void* userData_ = nullptr;
  std::atomic<uint64_t> modCounter_{0};
};

}  // namespace obvh::api
