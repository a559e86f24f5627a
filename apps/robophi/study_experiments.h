#pragma once
// The paper's experiments (MODEL §6, docs/robotics.md "Experiments") played from
// their scene files as `robophi run` plays them, with their outcomes and wall
// times: `robophi study experiments`.

#include <atomic>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "run/runner.h"

namespace robophi::cli {

/// What an experiment measured beyond the run report: figures for the record
/// (JSON, the unit in the key's name) and the same in words for the table.
struct ExperimentFigures {
  nlohmann::ordered_json values = nlohmann::ordered_json::object();
  std::vector<std::string> words;
};

/// Watches one run: an optional hook between steps, then the figures from the
/// final state and the report.
struct ExperimentProbe {
  StepTask betweenSteps;
  std::function<void(const Scene&, const State& last, const RunReport&, ExperimentFigures&)> finish;
};

/// One experiment: a scene file and what to measure on it, or a fixed note (an
/// experiment measured elsewhere, e.g. by a test).
struct Experiment {
  /// Stable key of the record, e.g. "wheel_cube"; --filter matches it and the title.
  std::string id;
  /// The paper's number ("1" .. "6") or section ("§5.1").
  std::string number;
  std::string title;
  /// Relative to the working folder (the repository root); empty for a note.
  std::string scene;
  /// The outcome of an experiment that is not run here.
  std::string note;
  std::function<ExperimentProbe(const Scene&)> probe;
};

/// In the order of the table.
std::vector<Experiment> paperExperiments();

/// The outcome of one experiment.
struct ExperimentResult {
  std::string id, number, title, scene;
  /// "ok", "stalled", "diverged", "interrupted" (RunReport::status), "load error", or "not run"
  /// for a note.
  std::string status = "not run";
  std::string failure;
  double simulatedSeconds = 0.0, wallSeconds = 0.0;
  std::int64_t steps = 0, rejected = 0;
  double energyDrift = 0.0, externalWork = 0.0;
  std::vector<std::string> events;
  ExperimentFigures figures;
  /// A note, or a run that ended with status ok.
  bool ok() const { return status == "ok" || status == "not run"; }
};

/// Loads the scene and runs it (nothing written), or returns the note. A set
/// `stop` flag ends the run early (status "interrupted").
ExperimentResult runExperiment(const Experiment& experiment,
                               const std::atomic<bool>* stop = nullptr);

/// The record of one result (bench/results/experiments.json "experiments").
nlohmann::ordered_json toJson(const ExperimentResult& result);
/// One line for the terminal.
std::string summaryLine(const ExperimentResult& result);
/// docs/experiments.md from a record {robophi, date, experiments: [...]}.
std::string experimentsMarkdown(const nlohmann::ordered_json& record);

}  // namespace robophi::cli
