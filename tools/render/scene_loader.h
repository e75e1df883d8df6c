// Reads a RenderScene from a glTF 2.0 file (.gltf, .glb) through tinygltf, or from an OBJ, PLY or STL
// mesh (one mesh, the default material, no lights or camera).
#pragma once

#include <string>

#include "render_scene.h"

namespace obvh::render {

// Throws std::runtime_error naming the file and what is wrong with it: a missing buffer, an
// accessor outside its buffer, an index out of range, a wrong component type, a node cycle, a
// required extension obvh does not read, non-finite positions, a scene without triangles.
RenderScene loadRenderScene(const std::string& path);

RenderScene loadGltfScene(const std::string& path);

}  // namespace obvh::render
