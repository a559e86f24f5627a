// `robophi run` as a user runs it: a results folder that is not robophi's is
// refused (exit 2) and kept, --force writes beside it, SIGINT and SIGTERM end a
// run with a whole folder marked interrupted, and the adaptive step's options
// are checked and used.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "output/results_folder.h"
#include "output/results_lock.h"
#include "output/run_reader.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;
using testing::writeText;

const std::string kScenes = ROBOPHI_SOURCE_DIR "/scenes/";

struct RunOutcome {
  int exitCode = -1;
  std::string errors;  // what it wrote to stderr
};

class RunCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = testing::makeTempFolder("robophi_run_command_");
    out_ = root_ / "out";
  }
  void TearDown() override { fs::remove_all(root_); }

  // `robophi run <args>`, to its end.
  RunOutcome run(const std::string& args) const {
    const fs::path errors = root_ / "stderr.txt";
    const std::string command =
        std::string(ROBOPHI_BINARY) + " run " + args + " > /dev/null 2> " + errors.string();
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readText(errors)};
  }

  // `robophi run <args>` started in the background, its stderr to `errors`.
  pid_t spawn(const std::vector<std::string>& args, const fs::path& errors) const {
    std::vector<std::string> words = {ROBOPHI_BINARY, "run"};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      // As from a terminal: the signals delivered, not blocked or ignored.
      sigset_t signals;
      sigemptyset(&signals);
      sigaddset(&signals, SIGINT);
      sigaddset(&signals, SIGTERM);
      sigprocmask(SIG_UNBLOCK, &signals, nullptr);
      const int err = open(errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int null = open("/dev/null", O_WRONLY);
      dup2(err, STDERR_FILENO);
      dup2(null, STDOUT_FILENO);
      execv(argv[0], argv.data());
      _exit(127);
    }
    return pid;
  }

  // Waits for `pid` (at most a minute, then kills it); `poke` is called every
  // 5 ms meanwhile. Returns its exit code, or -1 if a signal ended it.
  static int wait(pid_t pid, const std::function<void()>& poke = {}) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        ADD_FAILURE() << "robophi run did not end within a minute";
        return -1;
      }
      if (poke) poke();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // hand_grasp into out_ (it runs 50 s of model time in about 2 s here; 500 s
  // keeps it running well past the signal on a faster machine), sent `signal`
  // after `delay`; with `keepSignalling` the same signal again every 5 ms until
  // it ends: late signals, while it writes its results. (The same signal: a
  // pending SIGINT would be delivered before a first SIGTERM.)
  RunOutcome interruptLongRun(std::chrono::milliseconds delay, int signal, bool keepSignalling) {
    const fs::path errors = root_ / "stderr.txt";
    const pid_t pid =
        spawn({kScenes + "hand_grasp.json", "--duration", "500", "--quiet", "--out", out_.string()},
              errors);
    std::this_thread::sleep_for(delay);
    kill(pid, signal);
    const int exitCode = keepSignalling ? wait(pid, [&] { kill(pid, signal); }) : wait(pid);
    return {exitCode, readText(errors)};
  }

  nlohmann::json summary() const { return nlohmann::json::parse(readText(out_ / "summary.json")); }

  // The folder is whole: every file parses, the marker lists them, no staging left.
  void expectWholeInterruptedFolder() const {
    EXPECT_FALSE(fs::exists(root_ / ".out.partial"));
    ASSERT_TRUE(fs::exists(out_ / "summary.json"));
    const nlohmann::json s = summary();
    EXPECT_EQ(s["status"], "interrupted");
    EXPECT_GT(s["steps"].get<int>(), 0);
    EXPECT_LT(s["simulated_time_s"].get<double>(), s["duration_s"].get<double>());
    output::RunFolder folder;
    std::string error;
    EXPECT_TRUE(output::readRunFolder(out_.string(), /*needEnergy=*/true, folder, error)) << error;
    EXPECT_GT(folder.frameCount(), 1u);
    EXPECT_TRUE(folder.hasJoints && folder.hasContacts);
    const output::FolderContents contents = output::inspectResultsFolder(out_);
    EXPECT_TRUE(contents.marked);
    EXPECT_TRUE(contents.foreign.empty());
  }

  fs::path root_, out_;
};

TEST_F(RunCommandTest, AFolderWithAForeignFileIsRefusedWithExit2AndKept) {
  fs::create_directories(out_);
  writeText(out_ / "notes.txt", "mine");
  const RunOutcome o =
      run(kScenes + "pendulum.json --quiet --duration 0.05 --out " + out_.string());
  EXPECT_EQ(o.exitCode, 2) << o.errors;
  EXPECT_NE(o.errors.find(out_.string()), std::string::npos) << o.errors;
  EXPECT_NE(o.errors.find("notes.txt"), std::string::npos) << o.errors;
  EXPECT_NE(o.errors.find("--force"), std::string::npos) << o.errors;
  EXPECT_EQ(readText(out_ / "notes.txt"), "mine");
  EXPECT_FALSE(fs::exists(out_ / "summary.json"));
  EXPECT_FALSE(fs::exists(root_ / ".out.partial"));
}

TEST_F(RunCommandTest, ForceWritesBesideForeignFilesAndAPreviousResultIsReplaced) {
  const std::string args = kScenes + "pendulum.json --quiet --out " + out_.string();
  ASSERT_EQ(run(args + " --duration 0.05").exitCode, 0);
  ASSERT_EQ(run(args + " --duration 0.05").exitCode, 0);  // a previous result: replaced
  writeText(out_ / "notes.txt", "mine");
  EXPECT_EQ(run(args + " --duration 0.05").exitCode, 2);
  const RunOutcome forced = run(args + " --force --duration 0.02");
  EXPECT_EQ(forced.exitCode, 0) << forced.errors;
  EXPECT_EQ(readText(out_ / "notes.txt"), "mine");
  EXPECT_DOUBLE_EQ(summary()["duration_s"].get<double>(), 0.02);
  // Even --force does not replace a foreign file that has a result's name.
  fs::remove_all(out_);
  fs::create_directories(out_);
  writeText(out_ / "energy.csv", "mine");
  const RunOutcome clash = run(args + " --force --duration 0.02");
  EXPECT_EQ(clash.exitCode, 2);
  EXPECT_NE(clash.errors.find("energy.csv"), std::string::npos) << clash.errors;
  EXPECT_EQ(readText(out_ / "energy.csv"), "mine");
}

TEST_F(RunCommandTest, SigintAfterOneSecondLeavesAWholeFolderMarkedInterrupted) {
  const RunOutcome o = interruptLongRun(std::chrono::seconds(1), SIGINT, /*keepSignalling=*/false);
  EXPECT_EQ(o.exitCode, 130) << o.errors;
  EXPECT_NE(o.errors.find("interrupted by SIGINT"), std::string::npos) << o.errors;
  expectWholeInterruptedFolder();
  // Its page too (docs/output-format.md "Interrupted runs"), listed in the marker.
  EXPECT_TRUE(fs::exists(out_ / "replay.html"));
  EXPECT_NE(readText(out_ / "robophi-results.json").find("replay.html"), std::string::npos);
}

TEST_F(RunCommandTest, SigtermAndMoreSignalsWhileWritingStillLeaveAWholeFolder) {
  const RunOutcome o =
      interruptLongRun(std::chrono::milliseconds(500), SIGTERM, /*keepSignalling=*/true);
  EXPECT_EQ(o.exitCode, 143) << o.errors;
  EXPECT_NE(o.errors.find("interrupted by SIGTERM"), std::string::npos) << o.errors;
  expectWholeInterruptedFolder();
}

TEST_F(RunCommandTest, TheAdaptiveStepsOptionsAreUsedAndRecorded) {
  const RunOutcome o = run(kScenes +
                           "pendulum.json --quiet --duration 0.2 --tolerance 1e-7 "
                           "--min-step 1e-9 --max-step 2e-4 --max-penetration 0.05 --out " +
                           out_.string());
  ASSERT_EQ(o.exitCode, 0) << o.errors;
  const nlohmann::json adaptive = summary()["adaptive"];
  EXPECT_EQ(adaptive["energy_tolerance"].get<double>(), 1e-7);
  EXPECT_EQ(adaptive["min_step_s"].get<double>(), 1e-9);
  EXPECT_EQ(adaptive["max_step_s"].get<double>(), 2e-4);
  EXPECT_EQ(adaptive["max_penetration_fraction"].get<double>(), 0.05);
  EXPECT_LE(adaptive["largest_dt_s"].get<double>(), 2e-4);
}

TEST_F(RunCommandTest, BadNumbersAreBadInputWithAClearMessage) {
  const std::string base = kScenes + "pendulum.json --quiet --out " + out_.string();
  for (const std::string bad :
       {"--tolerance abc", "--tolerance 0", "--min-step -1e-9", "--max-step inf",
        "--max-penetration nan", "--dt 1e-3x", "--duration=-1"}) {
    const RunOutcome o = run(base + " " + bad);
    EXPECT_EQ(o.exitCode, 2) << bad << ": " << o.errors;
    const std::string option = bad.substr(0, bad.find_first_of(" ="));
    EXPECT_NE(o.errors.find(option), std::string::npos) << bad << ": " << o.errors;
    EXPECT_NE(o.errors.find("expected a positive number"), std::string::npos) << o.errors;
  }
  const RunOutcome crossed = run(base + " --min-step 1e-2 --max-step 1e-3");
  EXPECT_EQ(crossed.exitCode, 2);
  EXPECT_NE(crossed.errors.find("--min-step"), std::string::npos) << crossed.errors;
  EXPECT_EQ(run(base + " --no-such-option").exitCode, 2);  // not CLI11's own 109
  EXPECT_FALSE(fs::exists(out_));
}

TEST_F(RunCommandTest, HelpGivesTheAdaptiveOptionsWithTheirUnits) {
  const fs::path help = root_ / "help.txt";
  ASSERT_EQ(std::system((std::string(ROBOPHI_BINARY) + " run --help > " + help.string()).c_str()),
            0);
  const std::string text = readText(help);
  for (const char* part : {"--tolerance", "(-; energyTolerance", "--min-step", "(s; minStep",
                           "--max-step", "(s; maxStep", "--max-penetration",
                           "(-; maxPenetrationFraction", "--force", "never a stiffness"})
    EXPECT_NE(text.find(part), std::string::npos) << part << "\n" << text;
}

// The value after "default " in text[from, to) up to ':', ')' or ' ' ("" if none).
// (Plain text search: std::regex trips GCC 12's -Wmaybe-uninitialized in the
// sanitizer build.)
std::string defaultIn(const std::string& text, std::size_t from, std::size_t to) {
  const std::size_t at = text.find("default ", from);
  if (at == std::string::npos || at >= to) return "";
  const std::size_t begin = at + 8;
  const std::size_t end = text.find_first_of(":) \n", begin);
  return text.substr(begin, (end == std::string::npos ? text.size() : end) - begin);
}

// README's defaults of the adaptive step's options are those --help gives (and
// the code uses): "`--min-step S` (s; default 0: ..." against "default 0".
TEST_F(RunCommandTest, TheReadmesAdaptiveDefaultsAreThoseOfHelp) {
  const fs::path help = root_ / "help.txt";
  ASSERT_EQ(std::system((std::string(ROBOPHI_BINARY) + " run --help > " + help.string()).c_str()),
            0);
  const std::string helpText = readText(help);
  std::string readme = readText(ROBOPHI_SOURCE_DIR "/README.md");
  std::replace(readme.begin(), readme.end(), '\n', ' ');
  for (const std::string option :
       {"--tolerance", "--min-step", "--max-step", "--max-penetration"}) {
    // README: "`--min-step S` (s; default 0: ...": the option's backticked form, then
    // its parenthesis.
    const std::size_t inReadme = readme.find("`" + option + " ");
    ASSERT_NE(inReadme, std::string::npos) << option << ": not in README.md";
    const std::size_t open = readme.find("` (", inReadme);
    ASSERT_NE(open, std::string::npos) << option << ": no default in README.md";
    const std::string readmeDefault = defaultIn(readme, open, readme.find(')', open + 3) + 1);
    ASSERT_FALSE(readmeDefault.empty()) << option << ": no default in README.md";
    // --help: "--min-step NUMBER ... default 0" on the option's line.
    const std::size_t inHelp = helpText.find(option + " NUMBER");
    ASSERT_NE(inHelp, std::string::npos) << option << ": not in --help";
    const std::string helpDefault = defaultIn(helpText, inHelp, helpText.find('\n', inHelp));
    ASSERT_FALSE(helpDefault.empty()) << option << ": no default in --help";
    EXPECT_EQ(std::stod(readmeDefault), std::stod(helpDefault))
        << option << ": README.md says " << readmeDefault << ", --help " << helpDefault;
  }
}

// --dt is the step only: the model, its stiffness and so its highest frequency
// are the scene's whatever --dt says.
TEST_F(RunCommandTest, DtChangesTheStepNotTheStiffness) {
  std::vector<double> omega;
  for (const char* dt : {"1e-4", "2e-5"}) {
    const RunOutcome o =
        run(kScenes + "default.json --quiet --step constant --duration 0.001 --dt " + dt +
            " --out " + out_.string());
    ASSERT_EQ(o.exitCode, 0) << o.errors;
    EXPECT_EQ(summary()["dt_s"].get<double>(), std::stod(dt));
    omega.push_back(summary()["omega_max_rad_s"].get<double>());
  }
  EXPECT_EQ(omega[0], omega[1]);
}

// The run makes its replay page from the rows it wrote, as it wrote them (without
// reading its files back): byte for byte the page `robophi export html` makes
// from the files, for scenes with joints and contacts, goals and an environment
// (the hand's 151 frames: three pieces of its series written during the run).
TEST_F(RunCommandTest, TheRunsReplayPageIsThePageExportMakesFromItsFiles) {
  for (const char* scene : {"hand_grasp.json --duration 5", "wheel_cube_ramp.json --duration 0.5",
                            "arm_obstacle.json --duration 0.5", "pendulum.json --duration 0.3"}) {
    fs::remove_all(out_);
    const RunOutcome o = run(kScenes + scene + " --quiet --out " + out_.string());
    // (5: the arm's goal is not reached this soon; the page is written all the same.)
    ASSERT_TRUE(o.exitCode == 0 || o.exitCode == 5) << scene << ": " << o.errors;
    const fs::path exported = root_ / "exported.html";
    const std::string command = std::string(ROBOPHI_BINARY) + " export html " + out_.string() +
                                " --out " + exported.string() + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const std::string page = readText(out_ / "replay.html");
    EXPECT_GT(page.size(), 100000u) << scene;
    EXPECT_TRUE(page == readText(exported)) << scene << ": the pages differ";
  }
}

// A run's results folder, whole: its marker lists files that are all there,
// summary.json parses and the series read back (`why` says what is not).
bool wholeRunFolder(const fs::path& dir, std::string& why) {
  const output::FolderContents contents = output::inspectResultsFolder(dir);
  if (!contents.marked || !contents.foreign.empty()) {
    why = dir.string() + ": not marked, or holds files its marker does not list";
    return false;
  }
  const auto marker =
      nlohmann::json::parse(readText(dir / std::string(output::kResultsMarker)), nullptr, false);
  for (const auto& name : marker["files"]) {
    if (!fs::exists(dir / name.get<std::string>())) {
      why = dir.string() + ": " + name.get<std::string>() + " is listed but missing";
      return false;
    }
  }
  if (nlohmann::json::parse(readText(dir / "summary.json"), nullptr, false).is_discarded()) {
    why = dir.string() + ": summary.json does not parse";
    return false;
  }
  output::RunFolder folder;
  return output::readRunFolder(dir.string(), /*needEnergy=*/true, folder, why);
}

// Two runs on one folder. Started together, they overlap unless the machine
// runs one before the other starts (a loaded CI machine does): then both run in
// turn and the folder is whole. Held overlapping (the first stopped while it
// holds the lock), the second is refused at once (exit 2) naming the lock file
// and the holder.
TEST_F(RunCommandTest, TwoRunsOnOneFolderAtOnceOneIsRefusedByTheLock) {
  const std::vector<std::string> args = {
      kScenes + "pendulum.json", "--quiet", "--duration", "30", "--out", out_.string()};
  const fs::path lock = root_ / "out.lock";
  int refusedRounds = 0;
  for (int round = 0; round < 40; ++round) {
    const fs::path errorsA = root_ / "a.txt", errorsB = root_ / "b.txt";
    const bool held = round % 2 == 1;
    const pid_t a = spawn(args, errorsA);
    if (held) {
      // Stop the first run once it holds the lock: the lock file names its pid (the
      // holder writes it after its flock, on the file the path still names).
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      const std::string pidLine = std::to_string(a) + "\n";
      bool stopped = false;
      while (std::chrono::steady_clock::now() < deadline) {
        if (readText(lock) == pidLine) {
          kill(a, SIGSTOP);
          stopped = readText(lock) == pidLine;  // (still held: it had not just let go)
          if (!stopped) kill(a, SIGCONT);
          break;
        }
        if (waitpid(a, nullptr, WNOHANG) != 0) break;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      if (!stopped) {  // it ran through before it could be caught: try again
        wait(a);
        --round;
        continue;
      }
    }
    const pid_t b = spawn(args, errorsB);
    int exitB = 0;
    if (held) {
      exitB = wait(b);
      kill(a, SIGCONT);
    }
    const int exitA = wait(a);
    if (!held) exitB = wait(b);
    const std::string textA = readText(errorsA), textB = readText(errorsB);
    ASSERT_EQ(std::min(exitA, exitB), 0) << textA << textB;
    if (held) {
      ASSERT_EQ(exitB, 2) << "round " << round << ": the second ran beside the first\n" << textB;
    }
    if (std::max(exitA, exitB) == 2) {
      ++refusedRounds;
      const std::string& refused = exitA == 2 ? textA : textB;
      const pid_t holder = exitA == 2 ? b : a;
      EXPECT_NE(refused.find(lock.string()), std::string::npos) << refused;
      EXPECT_NE(refused.find("pid " + std::to_string(holder)), std::string::npos) << refused;
    } else {
      // In turn: both whole runs.
      ASSERT_EQ(std::max(exitA, exitB), 0) << textA << textB;
    }
    std::string why;
    ASSERT_TRUE(wholeRunFolder(out_, why)) << why;
    EXPECT_FALSE(fs::exists(lock));
  }
  EXPECT_GE(refusedRounds, 20);
}

// The lock is the folder's, whoever holds it: while this process holds it, a
// run and an export of the folder are refused (exit 2), naming this pid.
TEST_F(RunCommandTest, ARunOrAnExportOfALockedFolderIsRefused) {
  const std::string args = kScenes + "pendulum.json --quiet --duration 0.05 --out " + out_.string();
  ASSERT_EQ(run(args).exitCode, 0);
  const std::string exportHtml =
      std::string(ROBOPHI_BINARY) + " export html " + out_.string() + " > /dev/null 2> ";
  {
    const output::ResultsFolderLock lock(out_);
    const std::string holder = "pid " + std::to_string(getpid());
    const RunOutcome refused = run(args);
    EXPECT_EQ(refused.exitCode, 2);
    EXPECT_NE(refused.errors.find(holder), std::string::npos) << refused.errors;
    const int status = std::system((exportHtml + (root_ / "export.txt").string()).c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
    EXPECT_NE(readText(root_ / "export.txt").find((root_ / "out.lock").string()),
              std::string::npos)
        << readText(root_ / "export.txt");
  }
  EXPECT_EQ(std::system((exportHtml + "/dev/null").c_str()), 0);
}

// A run replacing an earlier result, killed outright at any moment: the folder
// holds the earlier or the new result, whole (or, killed between the two
// renames, the earlier one waits whole in .out.old and the next run puts it back).
TEST_F(RunCommandTest, AKillWhileAResultIsReplacedNeverLeavesTheFolderEmptyOrHalfWritten) {
  const std::vector<std::string> args = {
      kScenes + "hand_grasp.json", "--quiet", "--duration", "0.5", "--out", out_.string()};
  // The earlier result; then a replacement timed (the first run warms the caches).
  ASSERT_EQ(wait(spawn(args, root_ / "first.txt")), 0) << readText(root_ / "first.txt");
  const auto started = std::chrono::steady_clock::now();
  ASSERT_EQ(wait(spawn(args, root_ / "first.txt")), 0) << readText(root_ / "first.txt");
  const auto wall = std::chrono::duration_cast<std::chrono::microseconds>(
      std::chrono::steady_clock::now() - started);
  std::mt19937 random(40);
  std::uniform_int_distribution<std::int64_t> delay(0, wall.count() * 5 / 4);
  const fs::path previous = root_ / ".out.old";
  int killedBeforeTheEnd = 0, caughtReplacing = 0;
  for (int round = 0; round < 40; ++round) {
    const pid_t pid = spawn(args, root_ / "errors.txt");
    std::this_thread::sleep_for(std::chrono::microseconds(delay(random)));
    kill(pid, SIGKILL);
    if (wait(pid) != 0) ++killedBeforeTheEnd;
    std::string why;
    if (fs::exists(previous)) ++caughtReplacing;
    if (fs::exists(out_)) {
      ASSERT_TRUE(wholeRunFolder(out_, why)) << "round " << round << ": " << why;
    } else {
      ASSERT_TRUE(wholeRunFolder(previous, why)) << "round " << round << ": empty; " << why;
    }
  }
  EXPECT_GT(killedBeforeTheEnd, 10);
  RecordProperty("killed_while_replacing", caughtReplacing);
  ASSERT_EQ(wait(spawn(args, root_ / "last.txt")), 0) << readText(root_ / "last.txt");
  std::string why;
  EXPECT_TRUE(wholeRunFolder(out_, why)) << why;
  EXPECT_FALSE(fs::exists(previous));
  EXPECT_FALSE(fs::exists(root_ / ".out.partial"));
}

// A disk that fills during the run: exit 1 naming the file and the staging
// folder kept to look at, the earlier result as it was. (Needs root, to mount a
// small tmpfs.)
TEST_F(RunCommandTest, AFullDiskIsExit1NamingTheFileAndTheEarlierResultStays) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs (a disk that fills)";
  const fs::path disk = root_ / "disk";
  fs::create_directories(disk);
  if (mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=4m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here: " << std::strerror(errno);
  struct Unmount {
    fs::path dir;
    ~Unmount() { umount2(dir.c_str(), MNT_DETACH); }
  } unmount{disk};
  const fs::path out = disk / "out";
  const std::string args = kScenes + "pendulum.json --quiet --out " + out.string();
  const RunOutcome first = run(args + " --duration 0.05");
  ASSERT_EQ(first.exitCode, 0) << first.errors;
  std::map<std::string, std::string> earlier;
  for (const fs::directory_entry& entry : fs::directory_iterator(out))
    earlier[entry.path().filename().string()] = readText(entry.path());
  // All but 32 KiB of the disk taken.
  struct statvfs space {};
  ASSERT_EQ(statvfs(disk.c_str(), &space), 0);
  const auto available = static_cast<std::size_t>(space.f_bavail) * space.f_frsize;
  ASSERT_GT(available, std::size_t{65536});
  writeText(disk / "filler", std::string(available - 32768, 'x'));

  const RunOutcome full = run(args + " --duration 5");
  EXPECT_EQ(full.exitCode, 1) << full.errors;
  const fs::path staging = disk / ".out.partial";
  EXPECT_NE(full.errors.find("cannot write"), std::string::npos) << full.errors;
  EXPECT_NE(full.errors.find(staging.string() + "/"), std::string::npos) << full.errors;
  EXPECT_NE(full.errors.find("kept in " + staging.string()), std::string::npos) << full.errors;
  EXPECT_TRUE(fs::is_directory(staging));
  std::map<std::string, std::string> after;
  for (const fs::directory_entry& entry : fs::directory_iterator(out))
    after[entry.path().filename().string()] = readText(entry.path());
  EXPECT_TRUE(after == earlier) << "the earlier result changed";
  EXPECT_FALSE(fs::exists(disk / "out.lock"));
}

// Bounded work (issue 40): SIGTERM stops a run inside a constant step's split
// (a hundred 1e12 N/m rods at 1e-4 s, 380 times their critical step: the steps
// split into ever more substeps, minutes of them before the substep limit
// stops the run as stalled), the results so far written as for any interrupt.
// No wall time is asserted: the signal comes once the run has started (its
// staging folder exists) and a second later, and the minute of wait() is a guard.
TEST_F(RunCommandTest, SigtermStopsARunInsideASplitConstantStep) {
  std::string objects;
  for (int k = 0; k < 100; ++k) {
    const std::string y = std::to_string(0.3 * k);
    objects += std::string(k > 0 ? ",\n" : "") + R"(    {"name": "rod)" + std::to_string(k) +
               R"(", "type": "rope", "start": [0, )" + y + R"(, 0.021], "end": [0.5, )" + y +
               R"(, 0.2], "particles": 10, "mass": 1, "radius": 0.02, "stiffness": 1e12, )" +
               R"("velocity": [0, 0, -1]})";
  }
  const fs::path scene = root_ / "stiff_rods.json";
  writeText(scene, R"({"robophi": 1, "name": "stiff rods",
  "run": {"duration": 0.06, "dt": 1e-4, "step": "constant"},
  "environment": {"ground": true},
  "objects": [
)" + objects + "\n  ]\n}\n");
  const fs::path errors = root_ / "stderr.txt";
  const pid_t pid = spawn({scene.string(), "--quiet", "--out", out_.string()}, errors);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!fs::exists(root_ / ".out.partial") && waitpid(pid, nullptr, WNOHANG) == 0 &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  kill(pid, SIGTERM);
  const int exitCode = wait(pid);
  const std::string text = readText(errors);
  ASSERT_EQ(exitCode, 143) << text;
  EXPECT_NE(text.find("interrupted by SIGTERM"), std::string::npos) << text;
  const nlohmann::json s = summary();
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_LT(s["simulated_time_s"].get<double>(), 0.06);
  EXPECT_FALSE(fs::exists(root_ / ".out.partial"));
}

// Only regular files are read (issue 40): a FIFO given as the scene, as a bare
// URDF or as a scene's mesh, and a folder given as a URDF, are refused with exit
// 2 and a message naming them; none is waited on (wait()'s minute is a guard).
TEST_F(RunCommandTest, AFifoOrAFolderAsAnInputIsRefusedAndNeverWaitedOn) {
  const fs::path fifoScene = root_ / "scene.json", fifoUrdf = root_ / "robot.urdf";
  const fs::path fifoMesh = root_ / "part.stl", folderUrdf = root_ / "folder.urdf";
  ASSERT_EQ(mkfifo(fifoScene.c_str(), 0600), 0);
  ASSERT_EQ(mkfifo(fifoUrdf.c_str(), 0600), 0);
  ASSERT_EQ(mkfifo(fifoMesh.c_str(), 0600), 0);
  fs::create_directories(folderUrdf);
  const fs::path meshScene = root_ / "mesh_scene.json";
  writeText(meshScene, R"({"robophi": 1, "objects": [{"name": "part", "type": "mesh",
    "file": "part.stl", "center": [0, 0, 0.2], "mass": 1}]})");
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {fifoScene, "cannot open the scene file: is a FIFO (named pipe), not a regular file"},
      {fifoUrdf, "cannot read the file: is a FIFO (named pipe), not a regular file"},
      {meshScene, "part.stl': is a FIFO (named pipe), not a regular file"},
      {folderUrdf, "cannot read the file: is a folder, not a regular file"}};
  for (const auto& [input, message] : cases) {
    const fs::path errors = root_ / "stderr.txt";
    const int exitCode = wait(spawn({input.string(), "--quiet", "--out", out_.string()}, errors));
    const std::string text = readText(errors);
    EXPECT_EQ(exitCode, 2) << input << ": " << text;
    EXPECT_NE(text.find(message), std::string::npos) << input << ": " << text;
    EXPECT_NE(text.find(input.filename().string()), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out_));
  }
}

}  // namespace
}  // namespace robophi
