// Heatmaps of per-pixel counts (bounding-volume tests): a log-scale colour ramp from dark blue
// (1) through blue, red and yellow to white (256 and more), written through OpenImageIO.
#pragma once

#include <string>
#include <vector>

namespace obvh::tools {

// values: width * height counts, top row first. Throws std::runtime_error when the file cannot be written.
void writeHeatmap(const std::string& path, int width, int height, const std::vector<float>& values);

}  // namespace obvh::tools
