// A primitive as the builders see it: its bounds and an index into the scene's primitive table.
#pragma once

#include <cstdint>

#include "math/vec3.h"

namespace obvh {

struct PrimRef {
  Box3f bounds;
  uint32_t index = 0;
};

}  // namespace obvh
