#pragma once
/// \file
/// What a run did (summary.json, docs/output-format.md): the runner fills it,
/// the run writer writes it. Separate from the runner so that the writer needs
/// no runner.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/adaptive_step.h"
#include "robophi/world.h"

namespace robophi {

/// Where a run went wrong (diverged, stalled, energy account broken): the first
/// particle found non-finite, or the one with the most kinetic energy.
struct FailurePlace {
  double time = 0.0;
  std::int64_t step = 0;
  /// kNoParticle when no particle is to blame (the energy alone).
  ParticleIndex particle = kNoParticle;
  std::string object;
};

/// What a run did.
struct RunReport {
  /// "ok"; "diverged" when a state became NaN or infinite, or the energy grew
  /// over 100 times its initial scale (RunReport::initialScale) or the work
  /// done on it from outside, whichever is larger; "stalled" when
  /// the adaptive step fell below its floor, or the touching contacts overload
  /// the particles (particles inside one another); "interrupted" when a stop was
  /// requested (SIGINT, SIGTERM: RunOptions::stop) before the end: the results
  /// so far; "stopped" at RunOptions::stopAfter (a checkpoint to resume from);
  /// "energy_account_broken" when the energy account drifted past
  /// RunOptions::energyAccountBound; "goal_not_reached" when a goal of the
  /// scene was not reached by the end (outcomes). docs/output-format.md.
  std::string status = "ok";
  /// For a run that is not ok: what went wrong, with where and when.
  std::string failure;
  /// Where, for diverged, stalled and energy_account_broken runs.
  std::optional<FailurePlace> failurePlace;
  std::int64_t steps = 0;
  double simulatedTime = 0.0;
  double wallSeconds = 0.0;
  /// E + dissipated - external work at the start and end (J).
  double initialTotal = 0.0;
  double finalTotal = 0.0;
  /// The energy scale the drift is relative to (J): the largest kinetic +
  /// elastic energy (connectors, contacts) seen at any step, and never below
  /// the energy gravity can release in the scene (gravityEnergyScale: Σ m |g| ×
  /// the largest of the particles' bounding-box diagonal, their height above a
  /// plane and the largest free diameter, at the start) nor 1e-12 J.
  /// Neither depends on where z = 0 is.
  double energyScale = 0.0;
  /// The same scale at the start (J), which the runaway test uses.
  double initialScale = 0.0;
  /// (final total - initial total) / energyScale.
  double energyDrift = 0.0;
  /// The largest |total - initial total| / energyScale over the steps.
  double largestAccountError = 0.0;
  /// The bound on largestAccountError in use (RunOptions::energyAccountBound).
  double accountBound = 0.0;
  double dissipated = 0.0;
  /// Of it, the rigid trees' implicit contact loads' scheme loss (J, State::implicitLoss).
  double implicitLoss = 0.0;
  /// Work done between steps by the step tasks (J, EnergyTally::external).
  double externalWork = 0.0;
  StabilityEstimate stability;
  /// Accepted and rejected steps, step sizes (adaptive mode).
  AdaptiveStepStats adaptive;
  /// The adaptive step's floor in use (s, AdaptiveStepper::floor): minStep, or
  /// 1e-8 × the first trial step when minStep is 0. 0 in constant mode.
  double adaptiveFloor = 0.0;
  std::uint64_t stateHash = 0;
  std::vector<std::string> warnings;
  /// What the step tasks did (goal reached, virtual obstacles added, grasp
  /// verdict), in order; written to summary.json as "events".
  std::vector<std::string> events;
  /// The step tasks' outcomes as data (Task::outcomes merged): summary.json "outcomes".
  nlohmann::json outcomes = nlohmann::json::object();
  /// Names of the goals not reached at the end (status goal_not_reached).
  std::vector<std::string> goalsNotReached;
  /// Checkpoints written (checkpoint.json), and the time of the last (s).
  int checkpoints = 0;
  double lastCheckpointTime = -1.0;
  /// For a resumed run (robophi resume): the time of the checkpoint it started from (s).
  double resumedFrom = -1.0;
  bool ok() const { return status == "ok"; }
  /// The run ended soundly: ok, or only a goal was not reached by its end.
  bool sound() const { return ok() || status == "goal_not_reached"; }
  bool interrupted() const { return status == "interrupted" || status == "stopped"; }
  /// The run ended by numerical trouble (diverged, stalled).
  bool failed() const { return status == "diverged" || status == "stalled"; }
};

}  // namespace robophi
