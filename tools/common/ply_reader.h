// Reads the triangle meshes of PLY files (ASCII and binary little-endian, as the Stanford scan
// repository ships them): vertex x, y, z and face vertex-index lists; other properties are skipped.
// Debian 12 packages no PLY library, hence this small reader.
#pragma once

#include <string>

#include "scene_data.h"

namespace obvh::tools {

// Polygons with more than three vertices are split into fans. Throws std::runtime_error naming the
// file and the problem (unsupported format, truncated data, index out of range, ...).
MeshData readPly(const std::string& path);

}  // namespace obvh::tools
