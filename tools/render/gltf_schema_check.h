// The JSON types of a glTF document, checked before tinygltf reads it: tinygltf quietly replaces a
// property of the wrong type (a string where a number belongs, an object where an array belongs)
// by its default, which would render something other than the file says. Also refuses files that
// require an extension the renderer cannot read, before their data is misread.
#pragma once

#include <string>

namespace obvh::render {

// Throws std::runtime_error naming the property, e.g. "materials[0].pbrMetallicRoughness must be
// an object (it is an array)". Reads the JSON chunk of .glb files.
void checkGltfJsonTypes(const std::string& path);

}  // namespace obvh::render
