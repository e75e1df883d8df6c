// Renders one frame: camera rays per pixel (the pixel centre at one sample per pixel, jittered
// samples otherwise), radiance from the Integrator, rows in parallel with TBB.
#pragma once

#include <cstdint>
#include <vector>

#include "integrator.h"
#include "view_camera.h"

namespace obvh::render {

struct FrameSettings {
  int width = 640, height = 480;
  int samplesPerPixel = 1;
  uint64_t frame = 0;  // seeds the samplers, so animated frames do not repeat their noise
  bool progress = true;
  bool heatmap = false;  // count bounding-volume tests per pixel (needs obvh's statistics extension)
};

struct Frame {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear radiance, width * height * 3, top row first
  std::vector<float> volumeTests;  // with FrameSettings::heatmap: bounding-volume tests per pixel (all its rays)
  uint64_t rays = 0;       // queries sent to the library
  double seconds = 0.0;
};

// The mean of one pixel's samples (what renderFrame stores for it).
Vec3 renderPixel(const Integrator& integrator, const ViewCamera& camera, const FrameSettings& settings, int x, int y,
                 uint64_t& rays);

// Throws std::runtime_error when a heatmap is asked of a library without obvh's statistics extension.
Frame renderFrame(const Integrator& integrator, const ViewCamera& camera, const FrameSettings& settings);

}  // namespace obvh::render
