// robophi sweep as a user runs it (docs/sweep.md): every combination of the
// --set values and seeds is one row; the table is the same, byte for byte,
// with 1 or 2 threads and with 2 MPI ranks; a pointer that does not fit the
// scene is refused before anything runs, and nothing is written.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

// The arm reaching for its goal, 0.6 s of it, at two goal stiffnesses x two seeds.
const std::string kSweepArguments =
    " sweep " ROBOPHI_SOURCE_DIR
    "/scenes/arm_reach.json --set /robotics/goals/0/stiffness=50,200 --seeds 2 --duration 0.6 "
    "--quiet";

int runCommand(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(SweepCommand, EveryCombinationAndSeedIsOneRowTheSameOnOneOrTwoThreads) {
  const fs::path root = testing::makeTempFolder("robophi_sweep_");
  const fs::path log = root / "log.txt";
  ASSERT_EQ(runCommand(std::string(ROBOPHI_BINARY) + kSweepArguments + " --threads 1 --out " +
                           (root / "one").string(),
                       log),
            0)
      << readText(log);
  ASSERT_EQ(runCommand(std::string(ROBOPHI_BINARY) + kSweepArguments + " --threads 2 --out " +
                           (root / "two").string(),
                       log),
            0)
      << readText(log);
  const std::string one = readText(root / "one" / "sweep.csv");
  EXPECT_EQ(one, readText(root / "two" / "sweep.csv"));
  const auto rows = splitLines(one);
  ASSERT_EQ(rows.size(), 5u) << one;  // the header and 2 x 2 runs
  EXPECT_EQ(rows[0].rfind("run,/robotics/goals/0/stiffness,seed,status,", 0), 0u) << rows[0];

  const auto table = nlohmann::json::parse(readText(root / "one" / "sweep.json"));
  const auto& runs = table.at("runs");
  ASSERT_EQ(runs.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(runs[i].at("run").get<std::size_t>(), i);
    EXPECT_EQ(runs[i].at("/robotics/goals/0/stiffness").get<double>(), i < 2 ? 50.0 : 200.0);
    EXPECT_EQ(runs[i].at("seed").get<int>(), i % 2 == 0 ? 1 : 2);
    // 0.6 s is too short for the goal: a sound end, with the goal's outcome.
    EXPECT_EQ(runs[i].at("status").get<std::string>(), "goal_not_reached") << runs[i].dump();
    EXPECT_TRUE(runs[i].contains("outcomes/goals/0/final_distance_m")) << runs[i].dump();
  }
  // Seeds perturb the start, and the stiffness changes the motion: four states.
  EXPECT_NE(runs[0].at("state_hash"), runs[1].at("state_hash"));
  EXPECT_NE(runs[0].at("state_hash"), runs[2].at("state_hash"));
  // The stiffer goal pulls the tool nearer in the same time.
  EXPECT_LT(runs[2].at("outcomes/goals/0/final_distance_m").get<double>(),
            runs[0].at("outcomes/goals/0/final_distance_m").get<double>());
  // The report plots the figures against the parameter.
  const std::string html = readText(root / "one" / "report.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("outcomes/goals/0/final_distance_m"), std::string::npos);
  EXPECT_TRUE(fs::exists(root / "one" / "timing.csv"));
  fs::remove_all(root);
}

// Where the objects ended is in the table: a ball dropped on an overdamped ground
// (ζ = 2.2) rests with its centre at r - m g / κ_c, for each mass swept.
TEST(SweepCommand, TheTableSaysWhereEachObjectEnded) {
  const fs::path root = testing::makeTempFolder("robophi_sweep_end_");
  const fs::path log = root / "log.txt";
  ASSERT_EQ(runCommand(std::string(ROBOPHI_BINARY) + " sweep " ROBOPHI_SOURCE_DIR
                           "/scenes/ball_drop.json --set /objects/0/mass=0.2,0.4 "
                           "--set /contactPairs/0/contactDamping=2000 --quiet --out " +
                           (root / "sweep").string(),
                       log),
            0)
      << readText(log);
  const auto table = nlohmann::json::parse(readText(root / "sweep" / "sweep.json"));
  ASSERT_EQ(table.at("runs").size(), 2u);
  for (const auto& run : table.at("runs")) {
    const double mass = run.at("/objects/0/mass").get<double>();
    EXPECT_NEAR(run.at("end/ball/z").get<double>(), 0.05 - mass * 9.81 / 1e6, 1e-7) << run.dump();
    EXPECT_EQ(run.at("end/ball/x").get<double>(), 0.0);
    EXPECT_EQ(run.at("end/ball/y").get<double>(), 0.0);
    EXPECT_LT(run.at("end/ball/speed").get<double>(), 1e-4);
  }
  const std::string header = splitLines(readText(root / "sweep" / "sweep.csv")).at(0);
  EXPECT_NE(header.find(",end/ball/speed,end/ball/x,end/ball/y,end/ball/z"), std::string::npos)
      << header;
  // --end names the objects (none: no such columns); a name the scene lacks is
  // refused before anything runs, and nothing is written.
  const std::string sweep = std::string(ROBOPHI_BINARY) + " sweep " ROBOPHI_SOURCE_DIR
                            "/scenes/ball_drop.json --duration 0.1 --quiet ";
  ASSERT_EQ(runCommand(sweep + "--end none --out " + (root / "none").string(), log), 0)
      << readText(log);
  EXPECT_EQ(readText(root / "none" / "sweep.csv").find("end/"), std::string::npos);
  EXPECT_EQ(runCommand(sweep + "--end ball,bal --out " + (root / "bad").string(), log), 2);
  EXPECT_NE(readText(log).find("--end: the scene has no object 'bal' (its objects: 'ball')"),
            std::string::npos)
      << readText(log);
  EXPECT_FALSE(fs::exists(root / "bad"));
  fs::remove_all(root);
}

TEST(SweepCommand, ARunAsWrittenHasTheStateHashOfRobophiRun) {
  const fs::path root = testing::makeTempFolder("robophi_sweep_hash_");
  const fs::path log = root / "log.txt";
  // The scene's own value (100), seed 0: the scene as written.
  ASSERT_EQ(runCommand(std::string(ROBOPHI_BINARY) + " sweep " ROBOPHI_SOURCE_DIR
                           "/scenes/arm_reach.json --set /robotics/goals/0/stiffness=100 "
                           "--duration 0.6 --quiet --out " +
                           (root / "sweep").string(),
                       log),
            0)
      << readText(log);
  runCommand(std::string(ROBOPHI_BINARY) + " run " ROBOPHI_SOURCE_DIR
                 "/scenes/arm_reach.json --duration 0.6 --quiet --out " +
                 (root / "run").string(),
             log);
  const auto summary = nlohmann::json::parse(readText(root / "run" / "summary.json"));
  const auto table = nlohmann::json::parse(readText(root / "sweep" / "sweep.json"));
  ASSERT_EQ(table.at("runs").size(), 1u);
  EXPECT_EQ(table.at("runs")[0].at("seed").get<int>(), 0);
  EXPECT_EQ(table.at("runs")[0].at("state_hash"), summary.at("state_hash"));
  fs::remove_all(root);
}

TEST(SweepCommand, APointerThatDoesNotFitIsRefusedBeforeAnythingRuns) {
  const fs::path root = testing::makeTempFolder("robophi_sweep_bad_");
  const fs::path log = root / "log.txt";
  EXPECT_EQ(runCommand(std::string(ROBOPHI_BINARY) +
                           " sweep " ROBOPHI_SOURCE_DIR
                           "/scenes/arm_reach.json --set /robotics/nothing/0/stiffness=1 --out " +
                           (root / "out").string(),
                       log),
            2);
  EXPECT_NE(readText(log).find("/robotics/nothing/0/stiffness"), std::string::npos)
      << readText(log);
  EXPECT_FALSE(fs::exists(root / "out"));
  // A value the scene refuses: the loader's message, with the run it belongs to.
  EXPECT_EQ(runCommand(std::string(ROBOPHI_BINARY) +
                           " sweep " ROBOPHI_SOURCE_DIR
                           "/scenes/arm_reach.json --set /objects/0/mass=1,-1 --out " +
                           (root / "out").string(),
                       log),
            2);
  EXPECT_NE(readText(log).find("run 1 (/objects/0/mass=-1)"), std::string::npos) << readText(log);
  EXPECT_FALSE(fs::exists(root / "out"));
  fs::remove_all(root);
}

TEST(SweepCommand, TwoMpiRanksGiveTheTableOfOneProcess) {
#ifndef ROBOPHI_MPIEXEC
  GTEST_SKIP() << "robophi was built without MPI (libopenmpi-dev not found): the MPI sweep is "
                  "not tested";
#else
  const fs::path root = testing::makeTempFolder("robophi_sweep_mpi_");
  const fs::path log = root / "log.txt";
  ASSERT_EQ(runCommand(std::string(ROBOPHI_BINARY) + kSweepArguments + " --threads 1 --out " +
                           (root / "one").string(),
                       log),
            0)
      << readText(log);
  // Open MPI refuses root unless told (CI containers run as root).
  const std::string mpirun =
      std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + ROBOPHI_MPIEXEC +
      " -np 2 --oversubscribe ";
  ASSERT_EQ(runCommand(mpirun + ROBOPHI_BINARY + kSweepArguments + " --threads 1 --out " +
                           (root / "ranks").string(),
                       log),
            0)
      << readText(log);
  EXPECT_EQ(readText(root / "one" / "sweep.csv"), readText(root / "ranks" / "sweep.csv"));
  EXPECT_EQ(nlohmann::json::parse(readText(root / "one" / "sweep.json")),
            nlohmann::json::parse(readText(root / "ranks" / "sweep.json")));
  EXPECT_NE(readText(root / "ranks" / "report.html").find("2 ranks"), std::string::npos);
  fs::remove_all(root);
#endif
}

}  // namespace
}  // namespace robophi
