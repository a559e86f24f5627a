#pragma once
// Writes a run's files (docs/output-format.md) into a folder, streaming the
// sampled series as the run goes.

#include <cstdint>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "output/replay.h"
#include "output/run_report.h"
#include "output/world_view.h"
#include "robophi/scene/scene.h"

namespace robophi {

class RunWriter {
 public:
  /// Creates `dir` (which must not exist), writes the results marker
  /// (output/results_folder.h) that lists the series files, and opens them.
  /// With `gatherReplay`, also keeps the rows the replay page shows
  /// (takeReplayRows), so that the page is made without reading the files back.
  RunWriter(const std::string& dir, const Scene& scene, bool gatherReplay = false);
  /// Continues the series files already in `dir` (a resumed run, robophi
  /// resume): each is cut back to its length in `progress` (what progress()
  /// said at the checkpoint) and appended to. Throws std::runtime_error naming a
  /// file that is missing or shorter.
  RunWriter(const std::string& dir, const Scene& scene,
            const std::map<std::string, std::uintmax_t>& progress);

  /// The energy row of the world's current state, reached with a step of `dt` (s).
  void writeEnergyRow(const World& world, double dt);
  /// The frame of the world's current state: positions and velocities, the
  /// objects' energies and centres of mass, joints, contacts.
  void writeFrame(const World& world);
  /// Flushes the series files and returns their lengths (bytes), for a checkpoint.
  std::map<std::string, std::uintmax_t> progress();
  /// Writes `checkpoint` as checkpoint.json (whole or not at all) and lists it
  /// in the marker.
  void writeCheckpoint(const nlohmann::json& checkpoint);
  /// Lists model.json and summary.json in the marker, writes them and closes
  /// every file.
  void finish(const Scene& scene, const RunSettings& settings, const RunReport& report);
  /// The replay page's rows of everything written, when they were gathered and
  /// are whole (none once a number was not finite, or past kReplayGatherBytes:
  /// the page then reads the files).
  std::optional<ReplayRows> takeReplayRows() { return std::move(replay_); }

  /// The most bytes of replay rows a run keeps in memory.
  static constexpr std::size_t kReplayGatherBytes = std::size_t{256} << 20;

 private:
  std::ofstream open(const std::string& name, bool append = false);
  void writeObjects(const World& world);
  /// Appends `value` to line_ in its shortest round-trip form.
  void add(double value);
  /// Keeps line_ (a finished row) in `series` of the replay rows.
  void gather(ReplaySeries& series);
  /// Counts `bytes` more of replay rows; drops them all past the bound.
  void countGathered(std::size_t bytes);

  std::string dir_;
  std::vector<std::string> files_;  // written so far, for the marker
  std::ofstream energy_;
  std::ofstream particles_;
  std::ofstream joints_;
  std::ofstream contacts_;
  std::ofstream objects_;
  output::WorldView world_;  // world.json, for the replay (environment, goals, virtual obstacles)
  std::string line_;         // reused buffer for one CSV row
  bool lineFinite_ = true;   // whether every number of line_ is finite
  std::optional<ReplayRows> replay_;
};

/// Every file a run folder may hold besides the marker (docs/output-format.md).
const std::vector<std::string>& runFileNames();

/// The resolved model as JSON text (model.json).
std::string modelJson(const Scene& scene);

/// summary.json's text for a run (no NaN or infinity: such numbers are null and
/// listed in "non_finite").
std::string summaryJson(const Scene& scene, const RunSettings& settings, const RunReport& report);

}  // namespace robophi
