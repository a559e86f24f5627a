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
#include <utility>
#include <vector>

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

// Every file the run read is in its checkpoint with a digest: the scene, a mesh
// and a heightfield. Changing any refuses the resume (exit 2) naming the file;
// put back, the run goes on.
TEST_F(ResumeCommand, AChangedInputFileIsNamedAndRefused) {
  fs::create_directories(root_ / "parts");
  const std::string stl = testing::boxStl(0.1, 0.1, 0.1);
  const std::string pgm = "P2\n3 3\n255\n0 0 0\n0 10 0\n0 0 0\n";
  testing::writeText(root_ / "parts" / "cube.stl", stl);
  testing::writeText(root_ / "ground.pgm", pgm);
  testing::writeText(root_ / "scene.json", R"({
  "run": {"duration": 0.1, "dt": 1e-4, "step": "constant"},
  "environment": {"ground": true,
    "heightfield": {"origin": [-1, -1], "cellSize": [1, 1], "pgm": "ground.pgm", "maxHeight": 0.01}},
  "objects": [{"name": "part", "type": "mesh", "file": "parts/cube.stl", "center": [0, 0, 0.2],
               "mass": 1, "particles": 27}]
})");
  ASSERT_EQ(robophi("run scene.json -q --out p --stop-after 0.05"), 0) << errors();
  const nlohmann::json checkpoint =
      nlohmann::json::parse(readText(root_ / "p" / "checkpoint.json"));
  std::vector<std::string> inputs;
  for (const nlohmann::json& input : checkpoint["inputs"]) inputs.push_back(input["path"]);
  const std::string scene = fs::absolute(root_ / "scene.json").lexically_normal().string();
  const std::string mesh = fs::absolute(root_ / "parts" / "cube.stl").lexically_normal().string();
  const std::string field = fs::absolute(root_ / "ground.pgm").lexically_normal().string();
  EXPECT_EQ(inputs, (std::vector<std::string>{scene, mesh, field}));
  for (const auto& [path, text] : {std::pair{mesh, stl}, std::pair{field, pgm}}) {
    testing::writeText(path, text + "\n");
    EXPECT_EQ(robophi("resume p -q"), 2) << path;
    EXPECT_NE(errors().find("the run read " + path + ", which is missing or has changed"),
              std::string::npos)
        << errors();
    EXPECT_EQ(summary("p")["status"], "stopped");  // left as it was
    testing::writeText(path, text);
  }
  ASSERT_EQ(robophi("resume p -q"), 0) << errors();
  EXPECT_EQ(summary("p")["status"], "ok");
}

// A checkpoint's numbers are checked before anything runs: each out of its range
// is refused (exit 2) naming the field and the value.
TEST_F(ResumeCommand, EveryNumberOfACheckpointIsRangeChecked) {
  fs::copy_file(ROBOPHI_SOURCE_DIR "/scenes/pendulum.json", root_ / "pendulum.json");
  ASSERT_EQ(robophi("run pendulum.json -q --out p --stop-after 0.5"), 0) << errors();
  const fs::path file = root_ / "p" / "checkpoint.json";
  const std::string original = readText(file);
  struct Case {
    const char* pointer;
    nlohmann::json value;
    const char* expected;
  };
  const Case cases[] = {
      {"/state/time", "nan", "/state/time = \"nan\": expected a finite number >= 0"},
      {"/state/time", -1.0, "/state/time = -1.0: expected a finite number >= 0"},
      {"/state/time", 1e9,
       "/settings/duration = 2.0: expected at least /state/time = 1000000000.0"},
      {"/settings/duration", "inf", "/settings/duration = \"inf\": expected a finite number > 0"},
      {"/settings/dt", 0.0, "/settings/dt = 0.0: expected a finite number > 0"},
      {"/settings/fps", -60.0, "/settings/fps = -60.0: expected a finite number > 0"},
      {"/settings/adaptive/max_step", -1.0,
       "/settings/adaptive/max_step = -1.0: expected a number > 0"},
      {"/settings/adaptive/min_step", -1e-9,
       "/settings/adaptive/min_step = -1e-09: expected a finite number >= 0"},
      {"/energy_rate", "inf", "/energy_rate = \"inf\": expected a finite number > 0"},
      {"/state/step_count", -5, "/state/step_count = -5: expected a whole number >= 0"},
      {"/run/next_frame", 1.5, "/run/next_frame = 1.5: expected a whole number >= 0"},
      {"/run/checkpoints", -1, "/run/checkpoints = -1: expected a whole number >= 0"},
      {"/adaptive/accepted", -2, "/adaptive/accepted = -2: expected a whole number >= 0"},
      {"/state/position/0/2", "inf", "/state/position/0/2 = \"inf\": expected a finite number"},
  };
  for (const Case& c : cases) {
    nlohmann::json checkpoint = nlohmann::json::parse(original);
    checkpoint[nlohmann::json::json_pointer(c.pointer)] = c.value;
    testing::writeText(file, checkpoint.dump());
    EXPECT_EQ(robophi("resume p -q"), 2) << c.pointer;
    EXPECT_NE(errors().find(file.lexically_relative(root_).string() + ": " + c.expected),
              std::string::npos)
        << c.pointer << ": " << errors();
  }
  testing::writeText(file, original);
  ASSERT_EQ(robophi("resume p -q"), 0) << errors();
}

// A checkpoint belongs to its own folder: copied into another run's folder (the
// same scene, stopped at the same time, another step), it is refused (exit 2)
// naming a series file whose digest differs.
TEST_F(ResumeCommand, ACheckpointCopiedIntoAnotherRunsFolderIsRefused) {
  fs::copy_file(ROBOPHI_SOURCE_DIR "/scenes/pendulum.json", root_ / "pendulum.json");
  ASSERT_EQ(robophi("run pendulum.json -q --out a --stop-after 0.5"), 0) << errors();
  ASSERT_EQ(robophi("run pendulum.json -q --out b --stop-after 0.5 --tolerance 1e-6"), 0)
      << errors();
  const std::string b = readText(root_ / "b" / "checkpoint.json");
  fs::copy_file(root_ / "a" / "checkpoint.json", root_ / "b" / "checkpoint.json",
                fs::copy_options::overwrite_existing);
  EXPECT_EQ(robophi("resume b -q"), 2);
  EXPECT_NE(errors().find("is not the file this checkpoint was written with"), std::string::npos)
      << errors();
  EXPECT_NE(errors().find("b/energy.csv"), std::string::npos) << errors();
  testing::writeText(root_ / "b" / "checkpoint.json", b);
  ASSERT_EQ(robophi("resume b -q"), 0) << errors();
}

}  // namespace
}  // namespace robophi
