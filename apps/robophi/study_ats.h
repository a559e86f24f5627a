#pragma once
// The paper's ATS-against-CTS study (MODEL §4, §6.6), measured: each case has an
// analytic or reference answer; ATS is run with its default settings, CTS at the
// largest constant step that reaches the same error.

#include <functional>
#include <string>
#include <vector>

#include "robophi/world.h"

namespace robophi::cli {

/// One run of a case, ATS or CTS.
struct StudyRun {
  std::string mode;  // "ATS" or "CTS"
  double dt = 0.0;   // the constant step, or the mean adaptive step (s)
  std::int64_t steps = 0;
  std::int64_t rejected = 0;
  double wallSeconds = 0.0;
  double error = 0.0;
  bool finite = true;
};

/// A case: how to build it, how long to run it, and how far a run is from the answer.
struct StudyCase {
  std::string name;
  /// What the error measures, e.g. "rebound height (m)".
  std::string errorMeasure;
  double duration = 1.0;
  std::function<World()> make;
  /// Observes every accepted step (to catch an impact, an apex...).
  std::function<void(const World&)> observe;
  /// Resets the observer before a run.
  std::function<void()> reset;
  /// The error of the run just observed (>= 0).
  std::function<double(const World&)> error;
};

/// The four cases of issue 4: a stiff ball dropped on the ground, an oscillator
/// (undamped and damped), a stiff bar falling flat, the wheel and the cube.
std::vector<StudyCase> atsStudyCases();

/// One row of the study table.
struct StudyRow {
  std::string caseName, errorMeasure;
  StudyRun ats, cts;
  /// CTS steps / ATS steps.
  double stepRatio = 0.0;
  /// Wall time per step, ATS / CTS.
  double costPerStepRatio = 0.0;
  /// True when CTS did not reach the ATS error within its step budget.
  bool ctsBudgetExhausted = false;
};

/// Runs a case with ATS, then searches the largest CTS step with an error no
/// larger than ATS's (within `maxCtsSteps`).
StudyRow runStudyCase(const StudyCase& c, std::int64_t maxCtsSteps);

}  // namespace robophi::cli
