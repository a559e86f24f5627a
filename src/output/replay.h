#pragma once
/// \file
/// The replay page of a run: one self-contained HTML file (three.js inlined) that
/// shows the particles, connectors and contact forces over time in the world they
/// move in (environment, goals, paths, virtual obstacles), with energy, step and
/// joint plots. Opens from disk in a browser with no server and no network.
/// docs/viewer.md describes the page.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace robophi {

/// How to write the replay page.
struct ReplayOptions {
  /// The page stays under this size (bytes): frames (and, if need be, plot rows)
  /// are decimated to fit, and the page says so.
  double sizeCapBytes = 50e6;
  /// Where to write; empty means `runDir/replay.html`.
  std::string outputPath;
  /// The live view's page (docs/viewer.md "Live view"): the data object says so
  /// ("live"), and the page takes its frames from the WebSocket at /ws.
  bool live = false;
  /// Where the page's warnings go (a visual mesh not drawn: not found, not a
  /// regular file, past a budget), or nowhere.
  std::vector<std::string>* warnings = nullptr;
};

/// Reads the run folder `runDir` (model.json, particles.csv, energy.csv and, when
/// present, world.json (output/world_view.h), joints.csv and contacts.csv, whose
/// columns go into the page as they are; docs/output-format.md) and writes the
/// replay page, whole or not at all; a page written into a robophi results
/// folder is added to its marker. On failure returns false, writes nothing and
/// sets `error` to a message that names the file and what is wrong.
bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options, std::string& error);

/// One series of the page: its columns (the CSV header's) and its rows' numbers,
/// row-major (rows() × columns.size()), the doubles the CSV holds.
struct ReplaySeries {
  std::vector<std::string> columns;
  std::vector<double> values;
  std::size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }
};

/// A run's series as the page holds them, gathered by the run as it writes its
/// files (RunWriter), so that the page is made without reading them back.
struct ReplayRows {
  /// particles.csv's frames: each frame's t (s), and the particles' positions
  /// (m; frame, particle, x y z) in single precision, as the page draws them.
  std::vector<double> frameTime;
  std::vector<float> framePosition;
  ReplaySeries energy, joints, contacts;
  bool hasJoints = false, hasContacts = false;
  /// The rows' bytes, to bound what a run holds in memory.
  std::size_t bytes = 0;
};

/// The name of a run's replay page while it is written (in its folder, listed
/// in the marker until the page is ended).
inline constexpr const char* kReplayPagePartial = "replay.html.partial";

/// The replay page of a run written as the run goes (RunWriter, on its writer
/// thread): the page's head, then the pieces of its series as their rows come
/// (docs/viewer.md, "The page's data"), into `runDir`/replay.html.partial;
/// writeReplayHtml ends it. Removes what it wrote unless it was ended, and gives
/// up (removes it) once it is past `sizeCapBytes` (that page keeps only some
/// rows: writeReplayHtml writes it whole).
class ReplayPageStream {
 public:
  /// Into `runDir`, under the page's size cap (ReplayOptions::sizeCapBytes).
  ReplayPageStream(const std::string& runDir, double sizeCapBytes);
  ~ReplayPageStream();
  ReplayPageStream(const ReplayPageStream&) = delete;
  ReplayPageStream& operator=(const ReplayPageStream&) = delete;

  /// Writes the pieces whose rows are all in `rows` (of `particles` particles;
  /// rows only ever added, in time order); with `last`, all the rest.
  void write(const ReplayRows& rows, std::size_t particles, bool last = false);
  /// Whether what it wrote is still the page's beginning (no write failed, under
  /// the cap, the rows came in time order, not abandoned).
  bool usable() const;
  /// Removes what it wrote; it writes nothing more.
  void abandon();

 private:
  struct Pieces;
  std::unique_ptr<Pieces> state_;
  friend bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options,
                              const ReplayRows& rows, ReplayPageStream* stream, std::string& error);
};

/// The same page from `rows` (what the run wrote into `runDir`) and the folder's
/// model.json and world.json: byte for byte the page writeReplayHtml makes from
/// the folder's files. With `stream` (what the run wrote of it as it went), ends
/// that page when it keeps every row and goes into `runDir`; else writes it whole.
bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options,
                     const ReplayRows& rows, ReplayPageStream* stream, std::string& error);

}  // namespace robophi
