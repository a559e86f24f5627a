#pragma once
/// \file
/// Running a scene for a duration and writing its results (docs/output-format.md).

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

struct RunReport;

/// How to run. `settings` starts as the scene's and the command line overrides it.
struct RunOptions {
  RunSettings settings;
  /// Rows of energy.csv per model second (plus the first and last step).
  double energyRate = 1000.0;
  /// Output folder; empty writes nothing.
  std::string outDir;
  /// Also write outDir/replay.html (robophi export html).
  bool writeReplay = true;
  /// Called about every 0.1 s of wall time.
  std::function<void(const RunProgress&)> progress;
  /// Called after each accepted step, after the scene's own robotics tasks
  /// (docs/robotics.md): it may change the world through its public API (joint
  /// targets, World::mutableModel) and add lines to RunReport::events; returning
  /// false ends the run early (e.g. a goal reached).
  std::function<bool(World&, RunReport&)> betweenSteps;
};

/// What a run did.
struct RunReport {
  /// "ok"; "diverged" when a state became NaN or infinite, or the energy grew
  /// over 100 times its initial value (constant step);
  /// "stalled" when the adaptive step fell below its floor.
  std::string status = "ok";
  /// For a diverged run: which particle, when.
  std::string failure;
  std::int64_t steps = 0;
  double simulatedTime = 0.0;
  double wallSeconds = 0.0;
  /// E + dissipated - external work at the start and end (J), and their drift
  /// relative to the initial mechanical energy.
  double initialTotal = 0.0;
  double finalTotal = 0.0;
  double energyDrift = 0.0;
  double dissipated = 0.0;
  /// Work done between steps by robotics tasks and hooks (J, EnergyTally::external).
  double externalWork = 0.0;
  StabilityEstimate stability;
  /// Accepted and rejected steps, step sizes (adaptive mode).
  AdaptiveStepStats adaptive;
  std::uint64_t stateHash = 0;
  std::vector<std::string> warnings;
  /// What the robotics tasks did (goal reached, virtual obstacles added, grasp
  /// verdict), in order; written to summary.json as "events".
  std::vector<std::string> events;
  bool ok() const { return status == "ok"; }
};

/// Warnings about a scene before it runs (e.g. a step above the stability estimate).
std::vector<std::string> preflightWarnings(const RunSettings& settings,
                                           const StabilityEstimate& stability);

/// Runs the scene. When options.outDir is set, the results are written to a
/// staging folder and moved to outDir at the end (also for a diverged run, whose
/// summary says so). Throws std::runtime_error if the folder cannot be written.
RunReport runScene(const Scene& scene, const RunOptions& options, State* finalState = nullptr);

}  // namespace robophi
