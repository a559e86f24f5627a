// `robophi study ats` on a scene case without a robotics section, as a user runs
// it: it ends (it used to crash: a std::function wrapped the scene's empty task
// handle) and writes its row, CTS held to ATS's error with no more steps than
// ATS takes fewer of. Slow (a CTS search of the whole scene, about 15 s): under
// the ctest label slow, out of the sanitizer pass.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

class StudyAtsScene : public ::testing::TestWithParam<const char*> {};

TEST_P(StudyAtsScene, EndsAndWritesItsRow) {
  const fs::path root = testing::makeTempFolder("robophi_study_ats_");
  const std::string command = std::string(ROBOPHI_BINARY) + " study ats --filter '" + GetParam() +
                              "' --scenes " ROBOPHI_SOURCE_DIR "/scenes --out " + root.string() +
                              " > " + (root / "log.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << readText(root / "log.txt");
  ASSERT_EQ(WEXITSTATUS(status), 0) << readText(root / "log.txt");
  const std::string csv = readText(root / "ats-study.csv");
  // The case's row (its name quoted when it holds a comma or a space).
  std::size_t row = csv.find(std::string("\n\"") + GetParam() + "\"");
  if (row == std::string::npos) row = csv.find(std::string("\n") + GetParam());
  ASSERT_NE(row, std::string::npos) << csv;
  // step_ratio (CTS/ATS steps) is the second last column.
  const std::size_t end = csv.find('\n', row + 1);
  const std::string line = csv.substr(row + 1, end == std::string::npos ? end : end - row - 1);
  const std::size_t last = line.rfind(','), before = line.rfind(',', last - 1);
  const double ratio = std::stod(line.substr(before + 1, last - before - 1));
  std::printf("%s: CTS/ATS steps %.3f\n", GetParam(), ratio);
  EXPECT_GE(ratio, 1.0);
  fs::remove_all(root);
}

INSTANTIATE_TEST_SUITE_P(Slow, StudyAtsScene, ::testing::Values("scene: wheel and cube"));

}  // namespace
}  // namespace robophi
