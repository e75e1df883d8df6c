// The --quality option of the tools: low, medium or high, as rtcSetSceneBuildQuality takes them.
#pragma once

#include <embree3/rtcore.h>

#include <string>

namespace obvh::tools {

// Returns false for any other word.
inline bool parseBuildQuality(const std::string& word, RTCBuildQuality& quality) {
  if (word == "low") quality = RTC_BUILD_QUALITY_LOW;
  else if (word == "medium") quality = RTC_BUILD_QUALITY_MEDIUM;
  else if (word == "high") quality = RTC_BUILD_QUALITY_HIGH;
  else return false;
  return true;
}

}  // namespace obvh::tools
