#pragma once
// Writes a run's files (docs/output-format.md) into a folder, streaming the
// sampled series as the run goes.

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "output/replay.h"
#include "output/run_report.h"
#include "output/world_view.h"
#include "robophi/scene/scene.h"
#include "robophi/sensors.h"

namespace robophi {

/// The numbers of each row are taken on the run's thread and formatted and
/// written on a thread of the writer's own (where the machine has a second
/// core): the files are the same either way.
class RunWriter {
 public:
  /// Creates `dir` (which must not exist), writes the results marker
  /// (output/results_folder.h) that lists the series files, and opens them.
  /// With `replay` (the options the page will be made with), also keeps the
  /// rows the replay page shows (takeReplayRows), so that the page is made
  /// without reading the files back, and writes the page's series as they come
  /// (takeReplayPage), under the options' size cap.
  /// With `ownThread` (and a second core), formats and writes on a thread of
  /// its own; else on the caller's, at each hand-over.
  RunWriter(const std::string& dir, const Scene& scene, const ReplayOptions* replay = nullptr,
            bool ownThread = true);
  /// Continues the series files already in `dir` (a resumed run, robophi
  /// resume): each is cut back to its length in `progress` (what progress()
  /// said at the checkpoint) and appended to. Throws std::runtime_error naming a
  /// file that is missing or shorter.
  RunWriter(const std::string& dir, const Scene& scene,
            const std::map<std::string, std::uintmax_t>& progress, bool ownThread = true);
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

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
  /// are whole (none past kReplayGatherBytes: the page then reads the files).
  std::optional<ReplayRows> takeReplayRows() {
    drain();
    return std::move(replay_);
  }
  /// The replay page written so far (its head and the pieces of the rows
  /// gathered), to be ended by writeReplayHtml, or null (no rows gathered, or
  /// dropped). Call after takeReplayRows.
  std::unique_ptr<ReplayPageStream> takeReplayPage() {
    drain();
    return std::move(page_);
  }

  /// The most bytes of replay rows a run keeps in memory.
  static constexpr std::size_t kReplayGatherBytes = std::size_t{256} << 20;

 private:
  /// A row whose numbers wait in a Batch for the writer thread.
  enum class RowKind : std::uint8_t { kEnergy, kFrame, kObjects, kContact, kJoints, kSensors };
  /// Rows taken on the run's thread: their kinds and their numbers, in order.
  struct Batch {
    std::vector<RowKind> kinds;
    std::vector<double> values;
  };

  std::ofstream open(const std::string& name, bool append = false);
  /// Throws output::WriteError naming the file `name` when a write to `out` failed.
  void checkWritten(const std::ofstream& out, const std::string& name) const;
  /// checkWritten for every series file.
  void checkStreams() const;
  void takeObjects(const World& world);
  /// Sizes what a row holds (from the scene) and, with `ownThread` on a
  /// machine with a second core, starts the writer thread.
  void start(const Scene& scene, bool ownThread);
  /// Hands the rows taken so far to the writer thread (waiting for it to finish
  /// the previous batch first).
  void handOver();
  /// Hands over and waits until every row is written; rethrows what failed there.
  void drain();
  /// Ends the writer thread (after drain()).
  void stop();
  /// The writer thread: formats and writes the batches it is handed.
  void writeLoop();
  /// Formats and writes one batch's rows into their files.
  void writeBatch(const Batch& batch);
  /// Appends `value` to line_ in its shortest round-trip form.
  void add(double value);
  /// Keeps a row of `series` (its columns' count of numbers at `row`) for the
  /// replay page (replay_ set).
  void gather(ReplaySeries& series, const double* row);
  /// Counts `bytes` more of replay rows; past kReplayGatherBytes drops them all
  /// (replay_ reset) and returns false.
  bool reserveReplay(std::size_t bytes);

  std::string dir_;
  std::vector<std::string> files_;  // written so far, for the marker
  std::ofstream energy_;
  std::ofstream particles_;
  std::ofstream joints_;
  std::ofstream contacts_;
  std::ofstream objects_;
  std::ofstream sensors_;
  SensorSet sensorSet_;  // the scene's sensors (sensors.csv)
  output::WorldView world_;  // world.json, for the replay (environment, goals, virtual obstacles)
  std::string line_;         // reused buffer for one CSV row
  std::optional<ReplayRows> replay_;
  std::unique_ptr<ReplayPageStream> page_;  // the page as the rows come (with replay_)

  std::size_t particleCount_ = 0, jointCount_ = 0;  // a frame's particles, a joints row's joints
  Batch taken_;    // rows taken on the run's thread, not yet handed over
  Batch writing_;  // the batch the writer thread has (or had) to write
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool handed_ = false;         // writing_ holds rows the thread has not finished
  bool stopped_ = false;        // the thread is to end
  std::exception_ptr failure_;  // what went wrong on the writer thread
};

/// Every file a run folder may hold besides the marker (docs/output-format.md).
const std::vector<std::string>& runFileNames();

/// The resolved model as JSON text (model.json).
std::string modelJson(const Scene& scene);

/// summary.json's text for a run (no NaN or infinity: such numbers are null and
/// listed in "non_finite").
std::string summaryJson(const Scene& scene, const RunSettings& settings, const RunReport& report);

}  // namespace robophi
