// The "run" section of a scene, with the adaptive step's settings (MODEL §4,
// docs/adaptive-step.md).
#include <cmath>
#include "scene/scene_run.h"

#include <fmt/format.h>

namespace robophi::scene {

namespace {

// One run.adaptive key: an AdaptiveStepSettings field, its range and unit.
struct AdaptiveKey {
  const char* name;
  double AdaptiveStepSettings::*field;
  Interval range;
  const char* unit;
};

// The ranges keep the controller well defined: its factors are clamped into
// [0.1, shrinkFactor] and [1, growFactor], and it divides by the energy floor.
const AdaptiveKey kAdaptiveKeys[] = {
    {"energyTolerance", &AdaptiveStepSettings::energyTolerance, Interval::above(0.0), ""},
    {"minStep", &AdaptiveStepSettings::minStep, Interval::above(0.0), "s"},
    {"maxStep", &AdaptiveStepSettings::maxStep, Interval::above(0.0), "s"},
    {"lossToleranceFactor", &AdaptiveStepSettings::lossToleranceFactor, Interval::above(0.0), ""},
    {"energyFloor", &AdaptiveStepSettings::energyFloor, Interval::above(0.0), "J"},
    {"shrinkFactor", &AdaptiveStepSettings::shrinkFactor, Interval::closedOpen(0.1, 1.0), ""},
    {"growFactor", &AdaptiveStepSettings::growFactor, Interval::above(1.0), ""},
    {"safety", &AdaptiveStepSettings::safety, Interval::open(0.0, 1.0), ""},
    {"errorOrder", &AdaptiveStepSettings::errorOrder, Interval::atLeast(0.0), ""},
    {"maxPenetrationFraction", &AdaptiveStepSettings::maxPenetrationFraction,
     Interval::atLeast(0.0), ""},
    {"stabilitySafety", &AdaptiveStepSettings::stabilitySafety, Interval::openClosed(0.0, 1.0), ""},
    {"jumpLimit", &AdaptiveStepSettings::jumpLimit, Interval::atLeast(0.0), ""},
};

}  // namespace

void readAdaptiveSettings(DiagnosticSink& sink, const nlohmann::json& value,
                          const std::string& pointer, AdaptiveStepSettings& settings) {
  ObjectReader r(sink, value, pointer, "'run.adaptive'");
  if (!r.valid()) return;
  for (const AdaptiveKey& key : kAdaptiveKeys) {
    if (const auto x = r.number(key.name, key.range, key.unit)) settings.*key.field = *x;
  }
  settings.maxRejectionsInARow =
      r.integer("maxRejectionsInARow", 1).value_or(settings.maxRejectionsInARow);
  if (r.member("initialStep") != nullptr) {
    sink.errorAtKey(r.memberPointer("initialStep"),
                    "'initialStep' is not a key of 'run.adaptive': the first trial step is "
                    "'run.dt' (s)");
  }
  r.finish();
  if (settings.maxStep < settings.minStep) {
    sink.error(r.memberPointer(r.member("maxStep") ? "maxStep" : "minStep"),
               fmt::format("'maxStep' {} s must not be below 'minStep' {} s", settings.maxStep,
                           settings.minStep));
  }
}

RunSettings readRunSettings(DiagnosticSink& sink, const nlohmann::json* value) {
  RunSettings run;
  if (value == nullptr) return run;
  ObjectReader r(sink, *value, "/run", "'run'");
  run.duration = r.numberOr("duration", run.duration, Bound::kPositive, "s");
  run.dt = r.numberOr("dt", run.dt, Bound::kPositive, "s");
  run.fps = r.numberOr("fps", run.fps, Bound::kPositive, "frames/s");
  if (const auto name = r.string("integrator")) {
    if (!parseIntegrator(*name, run.integrator)) {
      sink.error("/run/integrator",
                 fmt::format("unknown integrator \"{}\"{} (expected symplectic, taylor or verlet)",
                             *name, didYouMean(*name, {"symplectic", "taylor", "verlet"})));
    }
  }
  if (const auto mode = r.string("step")) {
    if (*mode == "adaptive") {
      run.stepMode = StepMode::kAdaptive;
    } else if (*mode == "constant") {
      run.stepMode = StepMode::kConstant;
    } else {
      sink.error("/run/step",
                 fmt::format("unknown step mode \"{}\"{} (expected adaptive or constant)", *mode,
                             didYouMean(*mode, {"adaptive", "constant"})));
    }
  }
  if (const auto* adaptive = r.member("adaptive"))
    readAdaptiveSettings(sink, *adaptive, r.memberPointer("adaptive"), run.adaptive);
  r.finish();
  // The energy rate is the command line's (robophi run --energy-rate): not checked here.
  if (const auto problem = checkRunSettings(run, 0.0)) {
    const std::string& field = problem->field;
    sink.error(r.memberPointer(r.member(field) ? field : "duration"), problem->message);
  }
  return run;
}

}  // namespace robophi::scene

namespace robophi {

std::optional<RunSettingsProblem> checkRunSettings(const RunSettings& run, double energyRate) {
  if (run.dt > run.duration)
    return RunSettingsProblem{
        "dt", fmt::format("the step dt = {} s is longer than the duration {} s (a run is at "
                          "least one step)",
                          run.dt, run.duration)};
  const bool adaptive = run.stepMode == StepMode::kAdaptive;
  // An adaptive step without a ceiling (maxStep ∞, the default) counts in steps
  // of its first step dt.
  const double adaptiveStep =
      std::isfinite(run.adaptive.maxStep) ? run.adaptive.maxStep : run.dt;
  const double steps = run.duration / (adaptive ? adaptiveStep : run.dt);
  if (!(steps <= kMaxRunSteps))
    return RunSettingsProblem{
        adaptive ? "duration" : "dt",
        adaptive ? fmt::format("the duration {} s takes {:.3g} adaptive steps of {} = {} s, more "
                               "than the limit of {:.0e} steps (docs/scene-format.md#limits)",
                               run.duration, steps,
                               std::isfinite(run.adaptive.maxStep) ? "maxStep" : "the first step dt",
                               adaptiveStep, kMaxRunSteps)
                 : fmt::format("the duration {} s in constant steps of dt = {} s is {:.3g} steps, "
                               "more than the limit of {:.0e} steps (docs/scene-format.md#limits)",
                               run.duration, run.dt, steps, kMaxRunSteps)};
  if (!(run.duration * run.fps <= kMaxRunFrames))
    return RunSettingsProblem{
        "fps", fmt::format("the duration {} s at {} frames/s is {:.3g} frames, more than the "
                           "limit of {:.0e} frames (docs/scene-format.md#limits)",
                           run.duration, run.fps, run.duration * run.fps, kMaxRunFrames)};
  if (!(run.duration * energyRate <= kMaxRunEnergyRows))
    return RunSettingsProblem{
        "energyRate",
        fmt::format("the duration {} s at {} energy rows/s is {:.3g} rows of energy.csv, more "
                    "than the limit of {:.0e} rows (docs/scene-format.md#limits)",
                    run.duration, energyRate, run.duration * energyRate, kMaxRunEnergyRows)};
  return std::nullopt;
}

}  // namespace robophi
