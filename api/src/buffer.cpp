#include "buffer.h"

#include <cstdlib>
#include <cstring>

#include "api_error.h"

namespace obvh::api {

namespace {
constexpr size_t kPadding = 16;
constexpr size_t kAlignment = 64;
}  // namespace

Buffer::Buffer(Device* device, size_t byteSize) : device_(device), size_(byteSize), owned_(true) {
  // Reported once, before the allocation (post = false), as Embree's memory monitor contract has it:
  // a cancel there means the application does not count the bytes.
  const size_t allocated = (byteSize + kPadding + kAlignment - 1) / kAlignment * kAlignment;
  device->reportMemory(ssize_t(allocated), false);
  data_ = static_cast<unsigned char*>(std::aligned_alloc(kAlignment, allocated));
  if (!data_) {
    device->reportMemory(-ssize_t(allocated), true);
    fail(RTC_ERROR_OUT_OF_MEMORY, "out of memory allocating a buffer");
  }
  std::memset(data_, 0, allocated);
}

Buffer::Buffer(Device* device, void* shared, size_t byteSize)
    : device_(device), data_(static_cast<unsigned char*>(shared)), size_(byteSize), owned_(false) {}

Buffer::~Buffer() {
  if (owned_) {
    std::free(data_);
    const size_t allocated = (size_ + kPadding + kAlignment - 1) / kAlignment * kAlignment;
    try {
      device_->reportMemory(-ssize_t(allocated), true);
    } catch (...) {
    }
  }
}

size_t formatByteSize(int format) {
  const unsigned f = unsigned(format);
  const unsigned group = f >> 12;
  if (format == RTC_FORMAT_GRID) return 12;
  if (group == 0x9 && (f & 0xF00) != 0) {  // float matrices 0x9RC.
    const unsigned rows = (f >> 4) & 0xF, cols = f & 0xF;
    return sizeof(float) * rows * cols;
  }
  const unsigned count = f & 0xFF;
  switch (group) {
    case 0x1: case 0x2: return count <= 4 ? count : 0;
    case 0x3: case 0x4: return count <= 4 ? 2 * count : 0;
    case 0x5: case 0x6: return count <= 4 ? 4 * count : 0;
    case 0x7: case 0x8: return count <= 4 ? 8 * count : 0;
    case 0x9: return count <= 16 ? 4 * count : 0;
    default: return 0;
  }
}

}  // namespace obvh::api
