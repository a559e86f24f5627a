// `robophi validate` accepts exactly what `robophi run` accepts (issue 40): over
// every scene file of scenes/ and tests/scene/**, validate's verdict (exit 0 or
// 2) is run's (refused with exit 2 before it starts, or started). The run is
// kept short by --stop-after (one step), not by --duration, which would change
// the settings being checked (a duration shorter than the step is refused).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

// Every scene file (*.json) under scenes/ and tests/scene/, sorted.
std::vector<std::string> sceneFiles() {
  std::vector<std::string> files;
  for (const char* folder : {"scenes", "tests/scene"}) {
    const fs::path root = fs::path(ROBOPHI_SOURCE_DIR) / folder;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root))
      if (entry.is_regular_file() && entry.path().extension() == ".json")
        files.push_back(entry.path().lexically_relative(ROBOPHI_SOURCE_DIR).string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

struct Verdict {
  int exitCode = -1;
  std::string errors;
  bool refused() const { return exitCode == 2; }
};

class ValidateAndRun : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    root_ = testing::makeTempFolder("robophi_validate_run_");
    // Shipped scenes name their robots $(optenv ROBOPHI_ROBOTS_DIR ...).
    setenv("ROBOPHI_ROBOTS_DIR", ROBOPHI_ROBOTS_DIR, /*overwrite=*/0);
  }
  void TearDown() override { fs::remove_all(root_); }

  Verdict robophi(const std::string& args) const {
    const std::string command = std::string(ROBOPHI_BINARY) + " " + args + " > /dev/null 2> " +
                                (root_ / "stderr.txt").string();
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(root_ / "stderr.txt")};
  }

  fs::path root_;
};

TEST_P(ValidateAndRun, AgreeOnAcceptOrRefuse) {
  const std::string scene = std::string(ROBOPHI_SOURCE_DIR) + "/" + GetParam();
  const Verdict validate = robophi("validate " + scene);
  ASSERT_TRUE(validate.exitCode == 0 || validate.exitCode == 2)
      << "validate: exit " << validate.exitCode << "\n"
      << validate.errors;
  const Verdict run =
      robophi("run " + scene + " --quiet --stop-after 1e-12 --out " + (root_ / "out").string());
  EXPECT_EQ(validate.refused(), run.refused())
      << GetParam() << ": validate exit " << validate.exitCode << ", run exit " << run.exitCode
      << "\nvalidate: " << validate.errors << "\nrun: " << run.errors;
  if (run.refused()) {
    EXPECT_FALSE(fs::exists(root_ / "out")) << "a refused run wrote its folder";
  }
}

// A test's name from its file's path (non-alphanumerics → '_').
std::string fileLabel(const ::testing::TestParamInfo<std::string>& file) {
  std::string name = file.param;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Corpus, ValidateAndRun, ::testing::ValuesIn(sceneFiles()), fileLabel);

}  // namespace
}  // namespace robophi
