// Loads triangle meshes from files (OBJ through tinyobjloader, PLY, STL) into a SceneData.
#pragma once

#include <string>

#include "scene_data.h"

namespace obvh::tools {

// Throws std::runtime_error with a readable message when the file is missing or malformed.
SceneData loadObj(const std::string& path);

// What follows the last '.' of path (all of it when there is none), lower-cased: how the tools
// pick a file's reader or writer.
std::string lowerCaseExtension(const std::string& path);

// Chooses the reader by the file's extension: .obj, .ply or .stl.
SceneData loadMesh(const std::string& path);

}  // namespace obvh::tools
