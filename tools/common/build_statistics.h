// A library's own account of a build: both Embree and obvh print their tree's SAH cost when the
// device is created with "verbose=2" (line "total : sah = ..."), in the same convention (see
// backend/bvh/tree_statistics.h). The bench reads it from their standard output.
#pragma once

#include <functional>
#include <string>

namespace obvh::tools {

// Runs work with file descriptor 1 redirected to a temporary file; returns what was written.
std::string captureStandardOutput(const std::function<void()>& work);

// The first "total : sah = X" in a verbose build log; NaN when there is none.
double statisticsSahFromLog(const std::string& log);

}  // namespace obvh::tools
