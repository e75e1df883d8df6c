// RTCBuffer: library-owned or application-shared bytes, and a typed view of them for geometries.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>

#include "device.h"
#include "ref_counted.h"

namespace obvh::api {

class Buffer : public RefCounted {
 public:
  // Library-owned storage of byteSize bytes (plus padding so 16-byte loads of the last item are safe).
  Buffer(Device* device, size_t byteSize);
  // Application-owned storage; obvh never frees it.
  Buffer(Device* device, void* shared, size_t byteSize);
  ~Buffer() override;

  unsigned char* data() const { return data_; }
  size_t size() const { return size_; }
  Device* device() const { return device_.get(); }

  static Buffer* from(RTCBuffer handle) { return reinterpret_cast<Buffer*>(handle); }
  RTCBuffer handle() { return reinterpret_cast<RTCBuffer>(this); }

 private:
  Ref<Device> device_;
  unsigned char* data_ = nullptr;
  size_t size_ = 0;
  bool owned_ = false;
};

// A geometry's binding of (part of) a buffer: items of one format at a byte offset and stride.
struct BufferView {
  Ref<Buffer> buffer;
  size_t byteOffset = 0;
  size_t byteStride = 0;
  size_t itemCount = 0;
  int format = RTC_FORMAT_UNDEFINED;  // an RTCFormat value (see enum_bits.h)

  bool bound() const { return bool(buffer); }
  unsigned char* data() const { return buffer ? buffer->data() + byteOffset : nullptr; }
};

// Size in bytes of one item of format (0 for formats a buffer cannot hold).
size_t formatByteSize(int format);

}  // namespace obvh::api
