// Semiconductor-stack scenes: layers of uniformly spaced lines at an angle, vias between layers,
// stepped profiles and overlapping axis-aligned blocks, generated from a seed and parameters.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene_data.h"

namespace obvh::tools {

struct StackParams {
  int layers = 4;
  float dieSize = 100.f;           // the die is [0, dieSize]^2 in x and y
  float layerThickness = 2.f;      // each layer: a thin dielectric slab, then a row of lines on it
  std::vector<float> angles = {45.f};  // line angle in degrees per layer, repeated over the layers
  float linePitch = 2.f;           // distance between neighbouring line centres
  float lineWidthRatio = 0.5f;     // line width / pitch
  int viasPerLayer = 0;            // octagonal prisms joining a layer to the next
  int steppedProfiles = 0;         // staircases of `stepsPerProfile` boxes on top of the stack
  int stepsPerProfile = 8;
  int blocks = 0;                  // overlapping axis-aligned boxes inside the stack
  uint32_t seed = 1;
  size_t targetTriangles = 0;      // when set, linePitch is solved so that the count comes closest
};

// Triangles grouped by what they model, so writers can give each group its own material.
struct StackScene {
  std::string name;
  std::vector<std::string> groupNames;  // "slabs", "lines", "vias", "steps", "blocks" (non-empty groups)
  std::vector<MeshData> groups;
  size_t triangleCount() const;
  SceneData asScene() const;  // one geometry per group
};

StackScene generateStack(const StackParams& params, const std::string& name = "stack");

struct StackPreset {
  std::string name;
  std::string description;
  StackParams params;
};

// The seven presets reproduce the triangle counts of the published semiconductor-stack study
// (42,252; 1,548; 5,616; 515,824; 6,604; 6,912; 653,544) within 5%.
const std::vector<StackPreset>& stackPresets();
const StackPreset* findStackPreset(const std::string& name);

}  // namespace obvh::tools
