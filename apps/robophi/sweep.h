#pragma once
// robophi sweep: a batch study of one scene (docs/sweep.md). Every combination
// of the --set values (JSON-pointer overrides of the scene), each with its
// seeds (counter-based perturbations of the initial positions), is one run; the
// runs are independent and each is sequential, so the table is the same
// whatever the number of threads or MPI ranks that shared them out.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"

namespace robophi::cli {

/// One --set: a JSON pointer into the scene and the values it takes in turn.
struct SweepParameter {
  std::string pointer;
  std::vector<nlohmann::json> values;
};

/// Parses "POINTER=V1,V2,..." (values are JSON; a value that is not JSON is a
/// string; commas inside brackets or quotes do not split). Throws
/// std::invalid_argument naming the option and what is wrong.
SweepParameter parseSweepParameter(const std::string& option);

/// What the sweep runs.
struct SweepPlan {
  std::string scenePath;
  /// The scene as read (comments allowed), before any override.
  nlohmann::json scene;
  std::vector<SweepParameter> parameters;
  /// Seeds 1..seeds each perturb the initial positions; 0 seeds: one run per
  /// combination, as the scene is written (seed 0).
  int seeds = 0;
  /// The perturbation's size: each free particle moves by up to this fraction
  /// of its radius along each axis (-).
  double jitter = 0.01;
  /// > 0: the model time of every run (s), over the scene's run.duration.
  double duration = 0.0;
  /// The objects whose end state the table holds (--end), by name; empty: every
  /// object that touches something, when there are at most kEndStateObjects;
  /// {"none"}: none.
  std::vector<std::string> endObjects;
};

/// One run of the plan: the index of each parameter's value and the seed.
struct SweepCase {
  std::size_t index = 0;
  std::vector<std::size_t> choice;
  int seed = 0;
};

/// Every case in order: parameters vary with the last one fastest, seeds innermost.
std::vector<SweepCase> sweepCases(const SweepPlan& plan);

/// The scene text of a case (the overrides applied), or a message naming the
/// --set and the pointer that does not fit the scene (std::invalid_argument).
std::string caseSceneText(const SweepPlan& plan, const SweepCase& c);

/// Moves each free particle of `scene` by a counter-based random amount (the
/// same for the same seed, particle and axis on every machine): uniform in
/// ±jitter × radius per axis. Seed 0 changes nothing.
void perturbInitialPositions(Scene& scene, int seed, double jitter);

/// Scenes with more objects than this (a pile of single balls) get no end-state
/// columns unless --end names the objects.
inline constexpr std::size_t kEndStateObjects = 16;

/// The indices of the objects whose end state a row holds (SweepPlan::endObjects).
/// Throws std::invalid_argument naming an object the model does not have.
std::vector<std::size_t> endStateObjects(const Model& model, const std::vector<std::string>& names);

/// The row of one finished run: parameters, seed, status and figures, the
/// task outcomes flattened ("outcomes/goals/0/reached"), and where each object
/// ended ("end/<object>/x", y, z: its centre of mass, m; "/speed": that
/// centre's, m/s; the objects of endStateObjects); no wall time, so that rows
/// are the same however the runs were shared out.
nlohmann::json runCase(const SweepPlan& plan, const SweepCase& c, double& wallSeconds);

/// Writes sweep.csv, sweep.json and report.html (plots of the figures against
/// the parameters) into `dir`, and timing.csv (wall seconds: not part of the
/// table). Returns the names of the files written.
std::vector<std::string> writeSweepTables(const std::string& dir, const SweepPlan& plan,
                                          const std::vector<nlohmann::json>& rows,
                                          const std::vector<double>& wallSeconds,
                                          const std::string& sharing);

/// report.html's text: per numeric parameter the numeric figures of `names` (the
/// table's columns) plotted against it, each caption above its plot, the run,
/// the parameters and what came out (status, outcomes, failure) first, the
/// objects' end states collapsed; then the table in that order (numbers as
/// typed: the shortest text that reads back as the same double).
std::string sweepReportHtml(const SweepPlan& plan, const std::vector<nlohmann::json>& rows,
                            const std::vector<std::string>& names, const std::string& sharing);

}  // namespace robophi::cli
