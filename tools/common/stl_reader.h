// Reads STL triangle meshes, ASCII and binary (the format OpenFOAM's example geometry and most CAD
// exports ship in). STL repeats every vertex per facet; identical positions are merged, so shared
// edges share vertices as in the other formats. Debian 12 packages no STL library.
#pragma once

#include <string>

#include "scene_data.h"

namespace obvh::tools {

// Binary when the size matches the facet count at byte 80 (binary files may also begin with
// "solid"), else ASCII. Throws std::runtime_error naming the file and the problem (truncated
// data, a facet without three vertices, a number that does not parse or is not finite, ...).
MeshData readStl(const std::string& path);

}  // namespace obvh::tools
