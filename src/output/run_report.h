#pragma once
/// \file
/// What a run did (summary.json, docs/output-format.md): the runner fills it,
/// the run writer writes it. Separate from the runner so that the writer needs
/// no runner.

#include <cstdint>
#include <string>
#include <vector>

#include "robophi/adaptive_step.h"
#include "robophi/world.h"

namespace robophi {

/// What a run did.
struct RunReport {
  /// "ok"; "diverged" when a state became NaN or infinite, or the energy grew
  /// over 100 times its initial value (constant step); "stalled" when the
  /// adaptive step fell below its floor; "interrupted" when a stop was requested
  /// (SIGINT, SIGTERM: RunOptions::stop) before the end: the results so far.
  std::string status = "ok";
  /// For a diverged or stalled run: which particle, when.
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
  /// Work done between steps by the step tasks (J, EnergyTally::external).
  double externalWork = 0.0;
  StabilityEstimate stability;
  /// Accepted and rejected steps, step sizes (adaptive mode).
  AdaptiveStepStats adaptive;
  std::uint64_t stateHash = 0;
  std::vector<std::string> warnings;
  /// What the step tasks did (goal reached, virtual obstacles added, grasp
  /// verdict), in order; written to summary.json as "events".
  std::vector<std::string> events;
  bool ok() const { return status == "ok"; }
  bool interrupted() const { return status == "interrupted"; }
};

}  // namespace robophi
