// A primitive as the builders see it: its bounds and an index into the scene's primitive table.
#pragma once

#include <cstdint>

#include "math/vec3.h"
#include "memory/unwritten_allocator.h"

namespace obvh {

struct PrimRef {
  Box3f bounds;
  uint32_t index = 0;
};

// A build's table of refs; resize leaves the new refs unwritten.
using PrimRefs = UnwrittenVector<PrimRef>;

}  // namespace obvh
