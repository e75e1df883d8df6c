// Helpers of the file reader tests: files written to the test's temporary directory, and the error
// a reader reports for one.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>
#include <string>

namespace obvh::tools {

inline std::string writeFile(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

// The message of the std::runtime_error read(path) throws, or "" when it reads the file.
template <typename Reader>
std::string readError(Reader&& read, const std::string& path) {
  try {
    read(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace obvh::tools
