#pragma once
// Writes a run's files (docs/output-format.md) into a folder, streaming the
// sampled series as the run goes.

#include <fstream>
#include <string>
#include <vector>

#include "output/run_report.h"
#include "output/world_view.h"
#include "robophi/scene/scene.h"

namespace robophi {

class RunWriter {
 public:
  /// Creates `dir` (which must not exist), writes the results marker
  /// (output/results_folder.h) that lists the series files, and opens them.
  RunWriter(const std::string& dir, const Scene& scene);

  /// The energy row of the world's current state, reached with a step of `dt` (s).
  void writeEnergyRow(const World& world, double dt);
  /// The frame of the world's current state: positions, joints, contacts.
  void writeFrame(const World& world);
  /// Lists model.json and summary.json in the marker, writes them and closes
  /// every file.
  void finish(const Scene& scene, const RunSettings& settings, const RunReport& report);

 private:
  std::ofstream open(const std::string& name);

  std::string dir_;
  std::vector<std::string> files_;  // written so far, for the marker
  std::ofstream energy_;
  std::ofstream particles_;
  std::ofstream joints_;
  std::ofstream contacts_;
  std::string line_;         // reused buffer for one CSV row
  output::WorldView world_;  // world.json, for the replay (environment, goals, virtual obstacles)
};

/// Every file a run folder may hold besides the marker (docs/output-format.md).
const std::vector<std::string>& runFileNames();

/// The resolved model as JSON text (model.json).
std::string modelJson(const Scene& scene);

}  // namespace robophi
