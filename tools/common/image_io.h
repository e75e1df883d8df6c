// Writes images through OpenImageIO (format chosen by the file extension).
#pragma once

#include <string>
#include <vector>

namespace obvh::tools {

// rgb: width*height*3 values in [0,1]. Throws std::runtime_error when the file cannot be written.
void writeImage(const std::string& path, int width, int height, const std::vector<float>& rgb);

}  // namespace obvh::tools
