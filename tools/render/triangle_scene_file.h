// Scene files as bare triangles for the tools that trace geometry alone (obvh_bench,
// obvh_layouts): OBJ and PLY as tools::loadMesh reads them, and glTF 2.0 (.gltf, .glb) read by the
// renderer's loader, posed at time 0 and flattened into one world-space triangle mesh.
#pragma once

#include <string>

#include "scene_data.h"

namespace obvh::render {

// Throws std::runtime_error naming the file and what is wrong with it (see loadRenderScene).
tools::SceneData loadTriangleScene(const std::string& path);

}  // namespace obvh::render
