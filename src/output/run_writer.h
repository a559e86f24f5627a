#pragma once
// Writes a run's files (docs/output-format.md) into a folder, streaming the
// sampled series as the run goes.

#include <fstream>
#include <string>

#include "output/run_report.h"
#include "robophi/scene.h"

namespace robophi {

class RunWriter {
 public:
  /// Creates `dir` (which must not exist) and opens the series files.
  RunWriter(const std::string& dir, const Scene& scene);

  void writeEnergyRow(const State& state, double dt);
  void writeFrame(const Model& model, const State& state);
  /// Writes model.json and summary.json and closes every file.
  void finish(const Scene& scene, const RunSettings& settings, const RunReport& report);

 private:
  std::string dir_;
  std::ofstream energy_;
  std::ofstream particles_;
  std::ofstream joints_;
  std::ofstream contacts_;
  std::string line_;  // reused buffer for one CSV row
};

/// The resolved model as JSON text (model.json).
std::string modelJson(const Scene& scene);

}  // namespace robophi
