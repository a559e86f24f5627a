#pragma once
/// \file
/// Running a scene for a duration and writing its results (docs/output-format.md).
/// The runner knows nothing of robotics: what runs between steps comes in as
/// StepTasks (the scene's robotics tasks among them: robotics::makeSceneTasks).

#include <atomic>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "output/run_report.h"
#include "robophi/adaptive_step.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "robotics/task.h"

namespace robophi {

/// Where a run is, for progress displays.
struct RunProgress {
  double simulatedTime = 0.0;
  double duration = 0.0;
  std::int64_t steps = 0;
  double wallSeconds = 0.0;
};

/// The energy account's bound: a run whose |total - initial total| exceeds this
/// fraction of its energy scale (RunReport::energyScale) at any step ends with
/// status "energy_account_broken" (docs/output-format.md).
inline constexpr double kDefaultEnergyAccountBound = 0.05;

/// The most substeps one constant step may be split into (stepWithoutTunnelling:
/// the approach bound and the touching contacts' stability). A step that needed
/// more ends the run with status "stalled" (exit 3), naming the step and why
/// (docs/adaptive-step.md "The constant step"): a constant step far past the
/// critical step otherwise crawls on in ever smaller substeps (a 1e12 N/m rod
/// at 1e-4 s: 46 million substeps for 0.01 s, a minute of wall time).
inline constexpr std::int64_t kMaxConstantSubsteps = 100000;

/// How to run. `settings` starts as the scene's and the command line overrides it.
struct RunOptions {
  RunSettings settings;
  /// A bare URDF's load options (--package-path, --base), kept in the checkpoint
  /// so that `robophi resume` loads the robot as the run did.
  UrdfSceneOptions urdf;
  /// The most threads a step uses (World::setThreadCount): 0 = the cores available.
  /// Above 1 (or 0 on a machine with a second core) the run's output is also
  /// formatted and written on a thread of its own (RunWriter).
  /// Not part of the result: the state is bit-identical whatever the count.
  int threads = 0;
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
  /// Their outcomes (Task::outcomes) are merged into RunReport::outcomes, and
  /// their state is saved in checkpoints.
  std::vector<StepTask> tasks;
  /// The bound on the energy account's error (kDefaultEnergyAccountBound).
  double energyAccountBound = kDefaultEnergyAccountBound;
  /// Model time between checkpoints (s): outDir/checkpoint.json is replaced at
  /// the first step at or after every multiple of it. 0: none.
  double checkpointEvery = 0.0;
  /// > 0: the run stops at the first step at or after this model time (s),
  /// writes a checkpoint there and ends with status "stopped" (robophi resume
  /// continues it).
  double stopAfter = 0.0;
  /// A checkpoint (readCheckpoint) to continue from instead of the scene's
  /// initial state: robophi resume. outDir must be the folder that holds it;
  /// `settings` must be the checkpoint's (checkpointSettings).
  const nlohmann::json* resume = nullptr;
  /// When set and true, the run stops before its next step with status
  /// "interrupted" and writes the results so far (InterruptGuard sets one from
  /// SIGINT and SIGTERM).
  const std::atomic<bool>* stop = nullptr;
};

/// Warnings about a scene before it runs: a constant step above the critical step
/// (StabilityEstimate::criticalStep). None in adaptive mode, whose steps stay below it.
std::vector<std::string> preflightWarnings(const RunSettings& settings,
                                           const StabilityEstimate& stability);
/// The constant step's warning when it passes the critical step with the joint
/// drives' damping at the start (`start`: the evaluation at t = 0, the drives'
/// gains set); empty otherwise.
std::string driveStepWarning(const RunSettings& settings, const StabilityEstimate& stability,
                             const Evaluation& start);

/// Why an adaptive run of `settings` cannot end within kMaxRunSteps steps: the
/// adaptive step stays below stabilitySafety × the critical step (MODEL §2, §4),
/// so a model too stiff for its masses (a 1e-20 kg particle on a 1e4 N/m spring,
/// omega = 1e12 rad/s) would take more steps than the limit, for days. Empty
/// when it can, and for constant steps. robophi run and robophi validate refuse
/// such a scene alike.
std::string adaptiveStepLimitProblem(const RunSettings& settings,
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

/// Reads `dir`/checkpoint.json (a run folder).
/// Throws std::runtime_error naming the file and what is wrong.
nlohmann::json readCheckpoint(const std::string& dir);
/// What a checkpoint says of its run: the scene file, and the settings it ran
/// with (the command line's overrides included), the checkpoint interval and
/// the energy rate.
struct CheckpointedRun {
  std::string scenePath;
  /// The scene file's hash when the run started (fileHash).
  std::string sceneHash;
  /// A bare URDF's load options as the run had them.
  UrdfSceneOptions urdf;
  RunSettings settings;
  double energyRate = 1000.0;
  double checkpointEvery = 0.0;
  double energyAccountBound = kDefaultEnergyAccountBound;
  double time = 0.0;
};
CheckpointedRun checkpointedRun(const nlohmann::json& checkpoint);

}  // namespace robophi
