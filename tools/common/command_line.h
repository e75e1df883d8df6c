// Command-line helpers of the tools: whole-number option values and "--flag value" lists.
#pragma once

#include <cstdlib>
#include <optional>
#include <string>

namespace obvh::tools {

// The value if it is only digits and within 1..maxValue; otherwise nothing (the caller names the flag).
inline std::optional<long> parsePositiveNumber(const std::string& value, long maxValue) {
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || v <= 0 || v > maxValue) return std::nullopt;
  return v;
}

// Walks argv[1..] as "--flag value" pairs. fail(message) must not return; it gets "" for --help.
// handle(flag, value, positive) is called per pair; positive(maxValue) reads the value as a
// whole number in 1..maxValue or fails naming the flag.
template <typename Fail, typename Handle>
void readFlagValuePairs(int argc, char** argv, Fail&& fail, Handle&& handle) {
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--help" || flag == "-h") fail(std::string());
    if (i + 1 >= argc) fail("missing value for " + flag);
    const std::string value = argv[++i];
    const auto positive = [&](long maxValue) {
      const std::optional<long> v = parsePositiveNumber(value, maxValue);
      if (!v) fail("invalid value '" + value + "' for " + flag);
      return *v;
    };
    handle(flag, value, positive);
  }
}

}  // namespace obvh::tools
