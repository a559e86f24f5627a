#pragma once
// Small file helpers shared by the tests.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace robophi::testing {

/// The whole content of a text file ("" if it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `text` to a file, replacing it.
inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

}  // namespace robophi::testing
