// Writes generated scenes as OBJ or glTF 2.0 (.gltf with embedded buffer, or .glb), one object
// (OBJ) or one mesh primitive with its own material (glTF) per group.
#pragma once

#include <string>

#include "stack_generator.h"

namespace obvh::tools {

// Picks the format from the extension (.obj, .gltf, .glb); throws std::runtime_error on failure.
void writeStackScene(const StackScene& scene, const std::string& path);

}  // namespace obvh::tools
