#include "build_statistics.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <limits>
#include <regex>
#include <stdexcept>

namespace obvh::tools {

std::string captureStandardOutput(const std::function<void()>& work) {
  std::cout.flush();
  std::fflush(stdout);
  std::FILE* file = std::tmpfile();
  if (!file) throw std::runtime_error("cannot create a temporary file to capture standard output");
  const int saved = dup(1);
  dup2(fileno(file), 1);
  const auto restore = [&] {
    std::cout.flush();
    std::fflush(stdout);
    dup2(saved, 1);
    close(saved);
  };
  try {
    work();
  } catch (...) {
    restore();
    std::fclose(file);
    throw;
  }
  restore();
  std::string text;
  std::rewind(file);
  char buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) text.append(buffer, n);
  std::fclose(file);
  return text;
}

double statisticsSahFromLog(const std::string& log) {
  static const std::regex pattern(R"(total\s*:\s*sah\s*=\s*([0-9.eE+-]+))");
  std::smatch match;
  if (!std::regex_search(log, match, pattern)) return std::numeric_limits<double>::quiet_NaN();
  return std::stod(match[1].str());
}

}  // namespace obvh::tools
