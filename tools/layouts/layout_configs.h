// The BVH configurations the layout study compares (issue: OBB and hybrid BVHs on stacks), each
// with the device-config string that selects it through the Embree API.
#pragma once

#include <string>
#include <vector>

#include "builders/build_options.h"

namespace obvh::tools {

struct LayoutConfig {
  std::string name;          // short label for tables and heatmap file names
  std::string deviceConfig;  // the same configuration as an rtcNewDevice token list
  BuildOptions options;
};

const std::vector<LayoutConfig>& layoutConfigs();
const LayoutConfig* findLayoutConfig(const std::string& name);

}  // namespace obvh::tools
