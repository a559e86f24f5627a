// robophi resume DIR: continue a run from the checkpoint in its results folder
// (docs/output-format.md "Checkpoint and restart").
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "commands.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "robotics/tasks.h"
#include "run/checkpoint.h"
#include "run/interrupt.h"
#include "run/runner.h"
#include "scene_input.h"

namespace robophi::cli {

namespace {

struct ResumeArguments {
  std::string dir;
  double stopAfter = 0.0;
  bool quiet = false;
  int threads = 0;  // of the step; 0: the cores available
};

// A run killed outright (SIGKILL, a power cut) leaves its files in the staging
// folder beside DIR (.DIR.partial); when DIR does not exist, that folder becomes
// DIR so that the run can go on from its last checkpoint.
void adoptKilledRun(const std::string& dir) {
  namespace fs = std::filesystem;
  fs::path target(dir);
  if (target.filename().empty()) target = target.parent_path();
  const fs::path staging = output::stagingFolderOf(target);
  std::error_code ec;
  if (fs::exists(target, ec) || !fs::is_regular_file(staging / "checkpoint.json", ec)) return;
  fs::rename(staging, target, ec);
  if (!ec) {
    std::fprintf(stderr, "robophi resume: %s: taken from the killed run's staging folder %s\n",
                 target.string().c_str(), staging.string().c_str());
  }
}

int resumeCommand(const ResumeArguments& args) {
  InterruptGuard interrupt;
  // The folder is this resume's until it ends (its run takes the lock again);
  // a replacement a kill cut short is finished first.
  std::optional<output::ResultsFolderLock> lock;
  try {
    lock.emplace(args.dir);
    if (const std::string note = output::recoverResultsFolder(args.dir); !note.empty())
      std::fprintf(stderr, "robophi resume: %s\n", note.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robophi resume: %s\n", e.what());
    return kExitBadInput;
  }
  adoptKilledRun(args.dir);
  nlohmann::json checkpoint;
  CheckpointedRun saved;
  try {
    checkpoint = readCheckpoint(args.dir);
    // Its numbers in range, the files the run read unchanged, this folder's own.
    if (const std::string problem = checkpointProblem(args.dir, checkpoint); !problem.empty())
      throw std::runtime_error(problem);
    saved = checkpointedRun(checkpoint);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robophi resume: %s\n", e.what());
    return kExitBadInput;
  }
  // The scene as it was when the run started: a changed file would not go on
  // from the same model.
  if (fileHash(saved.scenePath) != saved.sceneHash) {
    std::fprintf(stderr,
                 "robophi resume: %s: the scene file %s is missing or has changed since the run "
                 "started (hash %s): the checkpoint cannot be continued\n",
                 args.dir.c_str(), saved.scenePath.c_str(), saved.sceneHash.c_str());
    return kExitBadInput;
  }
  auto scene = loadSceneOrReport(saved.scenePath, saved.urdf);
  if (!scene) return kExitBadInput;

  RunOptions options;
  options.settings = saved.settings;
  options.urdf = saved.urdf;
  options.threads = args.threads;
  options.energyRate = saved.energyRate;
  options.checkpointEvery = saved.checkpointEvery;
  options.energyAccountBound = saved.energyAccountBound;
  if (args.stopAfter > 0.0) {
    if (!(args.stopAfter > saved.time)) {
      std::fprintf(stderr,
                   "robophi resume: --stop-after %g s: the checkpoint is at t = %g s already\n",
                   args.stopAfter, saved.time);
      return kExitBadInput;
    }
    options.stopAfter = args.stopAfter;
  }
  options.outDir = args.dir;
  options.resume = &checkpoint;
  options.tasks = {robotics::makeSceneTasks(*scene)};
  options.stop = &InterruptGuard::flag();
  if (!args.quiet) {
    std::fprintf(stderr, "%s: resuming %s at t = %.6g s of %.6g s\n", args.dir.c_str(),
                 saved.scenePath.c_str(), saved.time, saved.settings.duration);
  }
  RunReport report;
  try {
    report = runScene(*scene, options);
  } catch (const output::ResultsFolderError& e) {
    std::fprintf(stderr, "robophi resume: %s\n", e.what());
    return kExitBadInput;
  } catch (const output::WriteError& e) {  // a full disk: the folder as it was
    std::fprintf(stderr, "robophi resume: %s\n", e.what());
    return kExitFailure;
  } catch (const nlohmann::json::exception& e) {
    std::fprintf(stderr, "robophi resume: %s/checkpoint.json: %s\n", args.dir.c_str(), e.what());
    return kExitBadInput;
  } catch (const std::runtime_error& e) {
    std::fprintf(stderr, "robophi resume: %s: %s\n", args.dir.c_str(), e.what());
    return kExitBadInput;
  }
  return reportRun(args.dir, options, report);
}

}  // namespace

void addResumeCommand(CLI::App& app, int& exitCode) {
  auto* cmd =
      app.add_subcommand("resume",
                         "Continue a run from the checkpoint in its results folder (robophi run "
                         "--checkpoint-every or --stop-after wrote it)");
  auto args = std::make_shared<ResumeArguments>();
  cmd->add_option("dir", args->dir, "The run's results folder (holds checkpoint.json)")->required();
  cmd->add_option("--stop-after", args->stopAfter,
                  "Stop again at model time S with a checkpoint (status \"stopped\")")
      ->type_name("S");
  cmd->add_option("--threads", args->threads,
                  "Threads of the step (default 0: the cores available); the results are the "
                  "same for every count")
      ->check(CLI::Range(0, 4096));
  cmd->add_flag("-q,--quiet", args->quiet, "No messages but the result");
  cmd->callback([args, &exitCode] { exitCode = resumeCommand(*args); });
}

}  // namespace robophi::cli
