// `robophi run ROBOT.xml` and `robophi validate ROBOT.xml` (scene/scene_mjcf.h): an
// MJCF arm runs, held by its position actuators; an element robophi cannot represent
// is refused (exit 2) naming it with its line; without libmujoco, the message says
// that MJCF needs libmujoco-dev.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "robophi/build/mjcf_multibody.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exitCode = -1;
  std::string errors;
};

Outcome robophiCommand(const fs::path& folder, const std::string& args) {
  const std::string command = std::string(ROBOPHI_BINARY) + " " + args + " > /dev/null 2> " +
                              (folder / "stderr.txt").string();
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(folder / "stderr.txt")};
}

TEST(MjcfCommand, AnMjcfArmRunsAndABallJointIsRefusedByName) {
  const fs::path folder = testing::makeTempFolder("robophi_mjcf_command_");
  const std::string arm = std::string(ROBOPHI_SOURCE_DIR) + "/tests/build/mjcf/arm.xml";
  const Outcome run =
      robophiCommand(folder, "run " + arm + " --duration 0.2 --out " + (folder / "arm").string());
  if (!build::mjcfAvailable()) {
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.errors.find("MJCF needs libmujoco-dev"), std::string::npos) << run.errors;
    fs::remove_all(folder);
    return;
  }
  EXPECT_EQ(run.exitCode, 0) << run.errors;
  EXPECT_TRUE(fs::exists(folder / "arm" / "summary.json"));
  const fs::path ball = folder / "ball.xml";
  std::ofstream(ball) << "<mujoco model=\"b\">\n<worldbody>\n<body name=\"arm\">\n"
                         "<joint name=\"shoulder_ball\" type=\"ball\" limited=\"true\" range=\"0 1\"/>\n"
                         "<geom type=\"sphere\" size=\"0.1\"/>\n</body>\n</worldbody>\n</mujoco>\n";
  const Outcome refused = robophiCommand(folder, "validate " + ball.string());
  EXPECT_EQ(refused.exitCode, 2);
  // (A ball joint loads, passive; its cone limit is what robophi cannot represent.)
  EXPECT_NE(refused.errors.find("ball.xml:4: error: <joint> 'shoulder_ball': a ball joint with a range"),
            std::string::npos)
      << refused.errors;
  fs::remove_all(folder);
}

}  // namespace
}  // namespace robophi
