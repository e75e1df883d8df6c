// Small glTF scenes that each call for a different set of renderer effects: shadows from several
// light types, alpha blending and masking, a dispersive prism, node animation with instancing.
#pragma once

#include <string>
#include <vector>

namespace obvh::tools {

struct ShowcaseScene {
  std::string name;
  std::string description;
};

const std::vector<ShowcaseScene>& showcaseScenes();

// Writes the named scene (.gltf or .glb); throws std::runtime_error for an unknown name.
void writeShowcaseScene(const std::string& name, const std::string& path);

}  // namespace obvh::tools
