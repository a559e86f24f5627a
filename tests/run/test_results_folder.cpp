// Results folders are safe (issue 10 item 6): robophi replaces only folders of
// its own, deletes nothing it did not write, and an interrupted run still leaves
// a whole folder, never a staging one.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "output/replay.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "output/run_reader.h"
#include "output/run_writer.h"
#include "output/vtk_export.h"
#include "robophi/scene/scene.h"
#include "robotics/tasks.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;
using testing::writeText;

class ResultsFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = testing::makeTempFolder("robophi_results_test_");
    out_ = root_ / "out";
    const SceneLoadResult loaded = loadSceneFile(ROBOPHI_SOURCE_DIR "/scenes/pendulum.json");
    ASSERT_TRUE(loaded.ok());
    scene_ = *loaded.scene;
    scene_.run.duration = 0.05;
  }
  void TearDown() override { fs::remove_all(root_); }

  RunOptions options() const {
    RunOptions o;
    o.settings = scene_.run;
    o.outDir = out_.string();
    o.writeReplay = false;  // the page is tested elsewhere; this keeps the runs short
    return o;
  }
  nlohmann::json summary() const { return nlohmann::json::parse(readText(out_ / "summary.json")); }
  bool stagingLeft() const { return fs::exists(root_ / ".out.partial"); }

  fs::path root_, out_;
  Scene scene_;
};

TEST_F(ResultsFolderTest, ARunWritesAMarkerListingItsFiles) {
  runScene(scene_, options());
  const output::FolderContents contents = output::inspectResultsFolder(out_);
  EXPECT_TRUE(contents.marked);
  EXPECT_EQ(contents.kind, "run");
  EXPECT_TRUE(contents.foreign.empty());
  for (const char* file : {"summary.json", "model.json", "energy.csv", "particles.csv"})
    EXPECT_NE(std::find(contents.owned.begin(), contents.owned.end(), file), contents.owned.end())
        << file;
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, AFolderWithAForeignFileIsRefusedAndKept) {
  fs::create_directories(out_);
  writeText(out_ / "notes.txt", "mine");
  const std::string problem = outputFolderProblem(options());
  EXPECT_NE(problem.find(out_.string()), std::string::npos) << problem;
  EXPECT_NE(problem.find("notes.txt"), std::string::npos) << problem;
  EXPECT_THROW(runScene(scene_, options()), output::ResultsFolderError);
  EXPECT_EQ(readText(out_ / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(out_ / "summary.json"));
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, AForeignFileAddedToAPreviousResultIsRefusedToo) {
  runScene(scene_, options());
  writeText(out_ / "notes.txt", "mine");
  EXPECT_THROW(runScene(scene_, options()), output::ResultsFolderError);
  EXPECT_EQ(readText(out_ / "notes.txt"), "mine");
}

TEST_F(ResultsFolderTest, APreviousResultAndAnEmptyFolderAreReplaced) {
  fs::create_directories(out_);
  runScene(scene_, options());  // into the empty folder
  // A previous file that the new run does not write goes too: it was robophi's.
  writeText(out_ / "replay.html", "<html>");
  output::addToResultsMarker(out_, "replay.html");
  RunOptions o = options();
  o.settings.duration = 0.02;
  runScene(scene_, o);
  EXPECT_DOUBLE_EQ(summary()["duration_s"].get<double>(), 0.02);
  EXPECT_FALSE(fs::exists(out_ / "replay.html"));
  EXPECT_TRUE(output::inspectResultsFolder(out_).foreign.empty());
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, ForceKeepsForeignFilesAndReplacesOnlyRobophis) {
  runScene(scene_, options());
  writeText(out_ / "notes.txt", "mine");
  fs::create_directories(out_ / "plots");
  writeText(out_ / "plots" / "a.png", "png");
  RunOptions o = options();
  o.force = true;
  o.settings.duration = 0.02;
  runScene(scene_, o);
  EXPECT_EQ(readText(out_ / "notes.txt"), "mine");
  EXPECT_EQ(readText(out_ / "plots" / "a.png"), "png");
  EXPECT_DOUBLE_EQ(summary()["duration_s"].get<double>(), 0.02);
  const output::FolderContents contents = output::inspectResultsFolder(out_);
  EXPECT_EQ(contents.foreign, (std::vector<std::string>{"notes.txt", "plots/"}));
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, ForceNeverReplacesAForeignFileNamedLikeAResult) {
  fs::create_directories(out_);
  writeText(out_ / "energy.csv", "my own energy");
  RunOptions o = options();
  o.force = true;
  const std::string problem = outputFolderProblem(o);
  EXPECT_NE(problem.find("energy.csv"), std::string::npos) << problem;
  EXPECT_THROW(runScene(scene_, o), output::ResultsFolderError);
  EXPECT_EQ(readText(out_ / "energy.csv"), "my own energy");
}

TEST_F(ResultsFolderTest, AKilledRunsStagingFolderIsClearedAForeignOneRefused) {
  // A run killed outright (SIGKILL) leaves its staging folder, marked.
  const fs::path staging = root_ / ".out.partial";
  fs::create_directories(staging);
  output::writeResultsMarker(staging, "run", {"energy.csv"});
  writeText(staging / "energy.csv", "t\n");
  runScene(scene_, options());
  EXPECT_FALSE(stagingLeft());
  EXPECT_TRUE(fs::exists(out_ / "summary.json"));

  fs::remove_all(out_);
  fs::create_directories(staging);
  writeText(staging / "notes.txt", "mine");
  EXPECT_THROW(runScene(scene_, options()), output::ResultsFolderError);
  EXPECT_EQ(readText(staging / "notes.txt"), "mine");
}

// A run killed while it writes its replay page (replay.html.partial, written as
// the run goes) leaves a staging folder that is wholly robophi's (the next run
// clears it); a page not ended is removed; a finished run's marker lists no
// partial page.
TEST_F(ResultsFolderTest, ThePageBeingWrittenIsListedUntilItIsEnded) {
  const fs::path staging = root_ / ".out.partial";
  {
    const ReplayOptions replay;
    RunWriter writer(staging.string(), scene_, &replay);
    World world(scene_.model, scene_.initial, scene_.run.integrator);
    for (int frame = 0; frame < 200; ++frame) {
      for (int k = 0; k < 10; ++k) ASSERT_EQ(world.step(scene_.run.dt), StepStatus::kOk);
      writer.writeEnergyRow(world, scene_.run.dt);
      writer.writeFrame(world);
    }
    (void)writer.progress();  // (every row written, the page's pieces with them)
    EXPECT_GT(fs::file_size(staging / kReplayPagePartial), 100000u);
    const output::FolderContents contents = output::inspectResultsFolder(staging);
    EXPECT_TRUE(contents.foreign.empty()) << contents.foreign.front();
  }
  EXPECT_FALSE(fs::exists(staging / kReplayPagePartial));
  fs::remove_all(staging);
  RunOptions o = options();
  o.writeReplay = true;
  runScene(scene_, o);
  EXPECT_TRUE(fs::exists(out_ / "replay.html"));
  const auto files = nlohmann::json::parse(readText(out_ / std::string(output::kResultsMarker)))["files"];
  EXPECT_NE(std::find(files.begin(), files.end(), "replay.html"), files.end());
  EXPECT_EQ(std::find(files.begin(), files.end(), kReplayPagePartial), files.end());
}

TEST_F(ResultsFolderTest, AVtkExportInsideARunFolderIsRobophisAndGoesWithIt) {
  runScene(scene_, options());
  std::string error;
  ASSERT_TRUE(writeVtkSeries(out_.string(), (out_ / "vtk").string(), error)) << error;
  EXPECT_EQ(output::inspectResultsFolder(out_ / "vtk").kind, "vtk");
  const output::FolderContents contents = output::inspectResultsFolder(out_);
  EXPECT_TRUE(contents.foreign.empty());
  runScene(scene_, options());  // the stale export goes with the run it came from
  EXPECT_FALSE(fs::exists(out_ / "vtk"));
  // The export refuses a folder that is not its own; a run refuses an export's.
  EXPECT_FALSE(writeVtkSeries(out_.string(), out_.string(), error));
  EXPECT_NE(error.find("run results"), std::string::npos) << error;
  const fs::path foreign = root_ / "mine";
  fs::create_directories(foreign);
  writeText(foreign / "notes.txt", "mine");
  EXPECT_FALSE(writeVtkSeries(out_.string(), foreign.string(), error));
  EXPECT_NE(error.find("notes.txt"), std::string::npos) << error;
  EXPECT_EQ(readText(foreign / "notes.txt"), "mine");
  ASSERT_TRUE(writeVtkSeries(out_.string(), (root_ / "vtk").string(), error)) << error;
  RunOptions o = options();
  o.outDir = (root_ / "vtk").string();
  EXPECT_NE(outputFolderProblem(o).find("vtk results"), std::string::npos);
}

TEST_F(ResultsFolderTest, AStopBeforeTheFirstStepStillWritesAWholeFolder) {
  const std::atomic<bool> stop{true};
  RunOptions o = options();
  o.stop = &stop;
  const RunReport report = runScene(scene_, o);
  EXPECT_EQ(report.status, "interrupted");
  EXPECT_EQ(report.steps, 0);
  EXPECT_EQ(summary()["status"], "interrupted");
  output::RunFolder run;
  std::string error;
  EXPECT_TRUE(output::readRunFolder(out_.string(), true, run, error)) << error;
  EXPECT_EQ(run.frameCount(), 1u);
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, AStopBetweenStepsEndsTheRunThereWithItsResultsSoFar) {
  std::atomic<bool> stop{false};
  RunOptions o = options();
  o.settings.stepMode = StepMode::kConstant;
  o.settings.duration = 1.0;
  o.stop = &stop;
  o.tasks.push_back([&stop](World& world, std::vector<std::string>&) {
    if (world.state().stepCount == 100) stop = true;  // as a signal handler would
    return true;
  });
  const RunReport report = runScene(scene_, o);
  EXPECT_EQ(report.status, "interrupted");
  EXPECT_EQ(report.steps, 100);
  const nlohmann::json s = summary();
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_EQ(s["steps"], 100);
  EXPECT_EQ(s["state_hash"], fmt::format("{:016x}", report.stateHash));
  output::RunFolder run;
  std::string error;
  ASSERT_TRUE(output::readRunFolder(out_.string(), true, run, error)) << error;
  EXPECT_DOUBLE_EQ(run.frameTime.back(), report.simulatedTime);  // the last state is a frame
  EXPECT_FALSE(stagingLeft());
}

TEST_F(ResultsFolderTest, TasksRunInOrderAndTheFirstToStopEndsTheRun) {
  std::vector<int> calls;
  RunOptions o = options();
  o.outDir.clear();
  o.tasks.push_back({});  // an empty task (a scene without robotics) is skipped
  o.tasks.push_back([&](World& world, std::vector<std::string>& events) {
    calls.push_back(1);
    if (world.state().stepCount < 3) return true;
    events.push_back("first stops");
    return false;
  });
  o.tasks.push_back([&](World&, std::vector<std::string>&) {
    calls.push_back(2);
    return true;
  });
  const RunReport report = runScene(scene_, o);
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.steps, 3);
  EXPECT_EQ(calls, (std::vector<int>{1, 2, 1, 2, 1}));
  EXPECT_EQ(report.events, std::vector<std::string>{"first stops"});
}

}  // namespace
}  // namespace robophi

namespace robophi {
namespace {

// A replacement killed between its two renames leaves the earlier results in
// .out.old and no out: the next run (or recoverResultsFolder) puts them back;
// killed after both, the earlier results are only deleted.
TEST_F(ResultsFolderTest, AReplacementCutShortIsUndoneByTheNextRun) {
  runScene(scene_, options());
  const std::string earlier = readText(out_ / "summary.json");
  const fs::path previous = output::previousFolderOf(out_);
  EXPECT_EQ(previous, root_ / ".out.old");
  fs::rename(out_, previous);
  const std::string note = output::recoverResultsFolder(out_);
  EXPECT_NE(note.find(previous.string()), std::string::npos) << note;
  EXPECT_EQ(readText(out_ / "summary.json"), earlier);
  EXPECT_FALSE(fs::exists(previous));

  fs::create_directories(previous);
  output::writeResultsMarker(previous, "run", {"summary.json"});
  writeText(previous / "summary.json", "{}");
  EXPECT_EQ(output::recoverResultsFolder(out_), "");
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_EQ(readText(out_ / "summary.json"), earlier);

  // A run does the same before it starts, then replaces the earlier results whole.
  fs::rename(out_, previous);
  RunOptions o = options();
  o.settings.duration = 0.02;
  runScene(scene_, o);
  EXPECT_DOUBLE_EQ(summary()["duration_s"].get<double>(), 0.02);
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_FALSE(stagingLeft());
}

// The lock is beside the folder while a run writes it, and gone after.
TEST_F(ResultsFolderTest, TheLockFileIsBesideTheFolderOnlyWhileARunHoldsIt) {
  EXPECT_EQ(output::lockFileOf(out_), root_ / "out.lock");
  EXPECT_EQ(output::lockFileOf(out_.string() + "/"), root_ / "out.lock");
  {
    const output::ResultsFolderLock lock(out_);
    EXPECT_EQ(readText(root_ / "out.lock"), std::to_string(getpid()) + "\n");
    runScene(scene_, options());  // the same process may take it again
    EXPECT_TRUE(fs::exists(root_ / "out.lock"));
  }
  EXPECT_FALSE(fs::exists(root_ / "out.lock"));
  EXPECT_TRUE(fs::exists(out_ / "summary.json"));
}

}  // namespace
}  // namespace robophi
