#pragma once
// The paper's ATS-against-CTS study (MODEL §4, §6.6), measured: each case has an
// analytic answer, a reference run, or (the experiment scenes) the energy
// account as its error; ATS runs with its default settings, CTS at the largest
// constant step whose error, bracketed, is no larger than ATS's.

#include <functional>
#include <string>
#include <vector>

#include "robophi/world.h"
#include "robotics/task.h"

namespace robophi::cli {

/// One run of a case, ATS or CTS.
struct StudyRun {
  std::string mode;  // "ATS" or "CTS"
  double dt = 0.0;   // the constant step, or the mean adaptive step (s)
  std::int64_t steps = 0;
  std::int64_t rejected = 0;
  double wallSeconds = 0.0;
  /// The error of this run; for CTS, the worst over the bracket of steps.
  double error = 0.0;
  /// CTS only: the error at `dt` itself (the bracket's centre).
  double centreError = 0.0;
  /// ATS only: the smallest and largest accepted steps (s), and the
  /// connectors' stability cap 0.9 × 2/ω_max at the start (s; infinite: none).
  double smallestStep = 0.0, largestStep = 0.0, stabilityCap = 0.0;
  bool finite = true;
};

/// The task a scene runs between steps (its robotics): the runner's StepTask
/// handle, empty when the scene has none (a std::function wrapping an empty
/// handle would not be empty, and calling it crashed the study on scenes
/// without robotics).
using StudyTask = StepTask;

/// A case: how to build it, how long to run it, and how far a run is from the answer.
struct StudyCase {
  std::string name;
  /// What the error measures, e.g. "rebound height (m)".
  std::string errorMeasure;
  /// "analytic", "reference" or "scene".
  std::string kind = "analytic";
  /// Whether the stiffness of the problem changes in time (impacts, a grasp
  /// closing, a vehicle on bumps): where the paper's margin is expected.
  bool stiffnessChanges = false;
  double duration = 1.0;
  std::function<World()> make;
  /// Makes the between-step task of a fresh run (empty: none).
  std::function<StudyTask()> makeTask;
  /// Observes every accepted step (to catch an impact, an apex...).
  std::function<void(const World&)> observe;
  /// Resets the observer before a run.
  std::function<void()> reset;
  /// The error of the run just observed (>= 0).
  std::function<double(const World&)> error;
  /// When set: the error the run already has for certain (a running maximum),
  /// so that a CTS run past its target can stop early.
  std::function<double()> errorSoFar;
};

/// The analytic cases (ball drops at κ_c = 1e7, 1e9, 1e10 N/m, oscillators,
/// pendulum with its pivot at z = 0), the reference cases (stiff bar, wheel and
/// cube on a slope), each with velocity Verlet and the paper's scheme, and the
/// experiment scenes found in `scenesDir` (hand_grasp, vehicle_hills,
/// wheel_cube, arm_obstacle, bar_flexion: their own integrator and tasks; a
/// missing file throws std::runtime_error naming it).
std::vector<StudyCase> atsStudyCases(const std::string& scenesDir);

/// One row of the study table.
struct StudyRow {
  std::string caseName, errorMeasure, kind;
  bool stiffnessChanges = false;
  StudyRun ats, cts;
  /// CTS steps / ATS steps.
  double stepRatio = 0.0;
  /// Wall time per step, ATS / CTS.
  double costPerStepRatio = 0.0;
  /// True when CTS did not reach the ATS error within its step budget.
  bool ctsBudgetExhausted = false;
};

/// The steps of the CTS bracket, as factors of the candidate step: a candidate
/// passes only when every one of them reaches the error (no lucky points).
const std::vector<double>& ctsBracket();

/// Runs a case with ATS, then searches the largest CTS step whose bracketed
/// error is no larger than ATS's (within `maxCtsSteps` per run).
StudyRow runStudyCase(const StudyCase& c, std::int64_t maxCtsSteps);

/// Writes DIR/ats-study.md, DIR/ats-study.csv and DIR/ats-study.svg (each
/// whole or not at all); nothing else.
void writeAtsStudy(const std::vector<StudyRow>& rows, const std::string& outDir);

}  // namespace robophi::cli
