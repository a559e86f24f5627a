#pragma once
/// \file
/// Running a scene for a duration and writing its results (docs/output-format.md).
/// The runner knows nothing of robotics: what runs between steps comes in as
/// StepTasks (the scene's robotics tasks among them: robotics::makeSceneTasks).

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "output/run_report.h"
#include "robophi/adaptive_step.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"

namespace robophi {

/// Where a run is, for progress displays.
struct RunProgress {
  double simulatedTime = 0.0;
  double duration = 0.0;
  std::int64_t steps = 0;
  double wallSeconds = 0.0;
};

/// A task run between steps (docs/robotics.md): it may change the world through
/// its edit API (joint targets, obstacles, velocities) and add lines to the
/// run's events (RunReport::events, summary.json "events"); returning false
/// ends the run (e.g. a goal reached). What it changes is booked as external
/// work (World::bookExternalWork).
using StepTask = std::function<bool(World& world, std::vector<std::string>& events)>;

/// How to run. `settings` starts as the scene's and the command line overrides it.
struct RunOptions {
  RunSettings settings;
  /// Rows of energy.csv per model second (plus the first and last step).
  double energyRate = 1000.0;
  /// Output folder; empty writes nothing. It must not exist, or hold nothing but
  /// a previous run's results (output/results_folder.h), unless `force`.
  std::string outDir;
  /// Also write into an outDir that holds files robophi did not write: they are
  /// kept; only robophi's own files are replaced (robophi run --force).
  bool force = false;
  /// Also write outDir/replay.html (robophi export html); not for an interrupted run.
  bool writeReplay = true;
  /// Called about every 0.1 s of wall time.
  std::function<void(const RunProgress&)> progress;
  /// Called after each accepted step, in order; the first that returns false
  /// ends the run (the later ones are not called then). Empty tasks are skipped.
  /// Callers put the scene's robotics tasks first (robotics::makeSceneTasks).
  std::vector<StepTask> tasks;
  /// When set and true, the run stops before its next step with status
  /// "interrupted" and writes the results so far (InterruptGuard sets one from
  /// SIGINT and SIGTERM).
  const std::atomic<bool>* stop = nullptr;
};

/// Warnings about a scene before it runs: a constant step above the critical step
/// (StabilityEstimate::criticalStep). None in adaptive mode, whose steps stay below it.
std::vector<std::string> preflightWarnings(const RunSettings& settings,
                                           const StabilityEstimate& stability);

/// Why options.outDir (or its staging folder beside it) may not receive the
/// results, naming the folder and what is in it; empty when it may.
std::string outputFolderProblem(const RunOptions& options);

/// Runs the scene. When options.outDir is set, the results are written to a
/// staging folder beside it (.NAME.partial) and moved to outDir at the end (also
/// for a diverged or interrupted run, whose summary says so); the staging folder
/// is removed if anything fails. Throws output::ResultsFolderError, before
/// running, when outDir may not receive the results (outputFolderProblem), and
/// std::runtime_error if the folder cannot be written.
RunReport runScene(const Scene& scene, const RunOptions& options, State* finalState = nullptr);

}  // namespace robophi
