// `robophi run --stop-after` and `robophi resume` as a user runs them: the
// resumed run ends with the state hash of an uninterrupted one; a folder without
// a checkpoint or a changed scene file is refused (exit 2). `robophi study
// experiments` run outside the checkout finds its scenes and writes only under --out.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

class ResumeCommand : public ::testing::Test {
 protected:
  void SetUp() override { root_ = testing::makeTempFolder("robophi_resume_command_"); }
  void TearDown() override { fs::remove_all(root_); }

  // `robophi <args>` in the folder root_, to its end; its exit code.
  int robophi(const std::string& args) const {
    const std::string command = "cd " + root_.string() + " && " + ROBOPHI_BINARY + " " + args +
                                " > stdout.txt 2> stderr.txt";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string errors() const { return readText(root_ / "stderr.txt"); }
  nlohmann::json summary(const std::string& dir) const {
    return nlohmann::json::parse(readText(root_ / dir / "summary.json"));
  }
  fs::path root_;
};

TEST_F(ResumeCommand, StopAndResumeEndsWithTheUninterruptedStateHash) {
  const std::string scene = ROBOPHI_SOURCE_DIR "/scenes/arm_obstacle.json";
  ASSERT_EQ(robophi("run " + scene + " -q --out whole"), 0) << errors();
  ASSERT_EQ(robophi("run " + scene + " -q --out cut --checkpoint-every 1 --stop-after 2.5"), 0)
      << errors();
  EXPECT_EQ(summary("cut")["status"], "stopped");
  EXPECT_TRUE(fs::exists(root_ / "cut" / "checkpoint.json"));
  EXPECT_FALSE(fs::exists(root_ / "cut" / "replay.html"));
  ASSERT_EQ(robophi("resume cut -q"), 0) << errors();
  const nlohmann::json whole = summary("whole"), cut = summary("cut");
  EXPECT_EQ(cut["status"], "ok");
  EXPECT_EQ(cut["state_hash"], whole["state_hash"]);
  EXPECT_EQ(cut["outcomes"], whole["outcomes"]);
  EXPECT_GE(cut["checkpoint"]["resumed_from_s"].get<double>(), 2.5);
  EXPECT_EQ(readText(root_ / "cut" / "particles.csv"), readText(root_ / "whole" / "particles.csv"));
  EXPECT_TRUE(fs::exists(root_ / "cut" / "replay.html"));
}

// A bare URDF run keeps its --package-path (and --base) in its checkpoint: the
// Panda's package:// meshes are found again on resume, and the resumed run ends
// with the uninterrupted one's state hash.
TEST_F(ResumeCommand, ABareUrdfResumesWithItsPackagePaths) {
  fs::copy(std::string(ROBOPHI_ROBOTS_DIR) + "/franka_panda", root_ / "franka_panda",
           fs::copy_options::recursive);
  const std::string run =
      "run franka_panda/panda.urdf --package-path franka_panda --base fixed "
      "-q --duration 0.2";
  ASSERT_EQ(robophi(run + " --out whole"), 0) << errors();
  ASSERT_EQ(robophi(run + " --out cut --stop-after 0.1"), 0) << errors();
  EXPECT_EQ(summary("cut")["status"], "stopped");
  const nlohmann::json checkpoint =
      nlohmann::json::parse(readText(root_ / "cut" / "checkpoint.json"));
  EXPECT_EQ(checkpoint["scene"]["urdf"]["package_paths"][0],
            fs::absolute(root_ / "franka_panda").string());
  EXPECT_EQ(checkpoint["scene"]["urdf"]["fixed_base"], true);
  ASSERT_EQ(robophi("resume cut -q"), 0) << errors();
  EXPECT_EQ(summary("cut")["status"], "ok");
  EXPECT_EQ(summary("cut")["state_hash"], summary("whole")["state_hash"]);
}

TEST_F(ResumeCommand, AGoalNotReachedExitsWithFive) {
  const std::string scene = ROBOPHI_SOURCE_DIR "/scenes/arm_obstacle.json";
  EXPECT_EQ(robophi("run " + scene + " -q --out short --duration 0.5"), 5) << errors();
  EXPECT_NE(errors().find("goal 'goal' not reached"), std::string::npos) << errors();
  const nlohmann::json s = summary("short");
  EXPECT_EQ(s["status"], "goal_not_reached");
  EXPECT_FALSE(s["outcomes"]["goals"][0]["reached"].get<bool>());
  EXPECT_EQ(s["goals_not_reached"][0], "goal");
}

TEST_F(ResumeCommand, ACheckpointThatDoesNotFitIsRefused) {
  EXPECT_EQ(robophi("resume nowhere"), 2);
  EXPECT_NE(errors().find("no checkpoint"), std::string::npos) << errors();
  // The scene file changed after the run started.
  fs::copy_file(ROBOPHI_SOURCE_DIR "/scenes/pendulum.json", root_ / "pendulum.json");
  ASSERT_EQ(robophi("run pendulum.json -q --out p --stop-after 0.5"), 0) << errors();
  testing::writeText(root_ / "pendulum.json", readText(root_ / "pendulum.json") + "\n// changed\n");
  EXPECT_EQ(robophi("resume p"), 2);
  EXPECT_NE(errors().find("has changed"), std::string::npos) << errors();
  EXPECT_EQ(summary("p")["status"], "stopped");  // left as it was
}

TEST_F(ResumeCommand, StudyExperimentsOutsideTheCheckoutWritesOnlyUnderOut) {
  ASSERT_EQ(robophi("study experiments --filter arm_reach --out results"), 0) << errors();
  EXPECT_TRUE(fs::exists(root_ / "results" / "experiments.md"));
  EXPECT_TRUE(fs::exists(root_ / "results" / "experiments.json"));
  EXPECT_FALSE(fs::exists(root_ / "bench"));
  EXPECT_FALSE(fs::exists(root_ / "docs"));
  // A scene folder that does not hold them is named.
  EXPECT_EQ(robophi("study experiments --filter arm_reach --scenes nowhere"), 2);
  EXPECT_NE(errors().find("nowhere"), std::string::npos) << errors();
}

}  // namespace
}  // namespace robophi
