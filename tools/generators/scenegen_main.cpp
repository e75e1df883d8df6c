// obvh_scenegen: writes the renderer's showcase scenes (glTF), each calling for different effects.
#include <cstdio>
#include <exception>
#include <string>

#include "showcase_scenes.h"

int main(int argc, char** argv) {
  const std::string first = argc > 1 ? argv[1] : "";
  if (first == "--list") {
    for (const auto& s : obvh::tools::showcaseScenes()) std::printf("%-10s %s\n", s.name.c_str(), s.description.c_str());
    return 0;
  }
  if (argc != 4 || std::string(argv[2]) != "--out") {
    std::fprintf(stderr, "usage: obvh_scenegen NAME --out FILE.gltf|FILE.glb\n       obvh_scenegen --list\n");
    return 2;
  }
  try {
    obvh::tools::writeShowcaseScene(argv[1], argv[3]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "obvh_scenegen: %s\n", e.what());
    return 1;
  }
  std::printf("wrote %s\n", argv[3]);
  return 0;
}
