#pragma once
// Small file helpers shared by the tests.

#include <filesystem>
#include <fstream>
#include <random>
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

/// A new folder under the system's temporary folder, `prefix` and a random number.
inline std::filesystem::path makeTempFolder(const std::string& prefix) {
  std::random_device seed;
  const auto dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(seed()));
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `text` to a file, replacing it.
inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

}  // namespace robophi::testing
