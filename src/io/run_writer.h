#pragma once
// Writes a run's files (docs/output-format.md) into a folder, streaming the
// sampled series as the run goes.

#include <fstream>
#include <string>

#include "robophi/runner.h"
#include "robophi/scene/scene.h"

namespace robophi {

class RunWriter {
 public:
  /// Creates `dir` (which must not exist) and opens the series files.
  RunWriter(const std::string& dir, const Scene& scene);

  /// The energy row of the world's current state, reached with a step of `dt` (s).
  void writeEnergyRow(const World& world, double dt);
  /// The frame of the world's current state: positions, joints, contacts.
  void writeFrame(const World& world);
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
