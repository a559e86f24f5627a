#pragma once
/// \file
/// The replay page of a run: one self-contained HTML file (three.js inlined) that
/// shows the particles, connectors and contact forces over time in the world they
/// move in (environment, goals, paths, virtual obstacles), with energy, step and
/// joint plots. Opens from disk in a browser with no server and no network.
/// docs/viewer.md describes the page.

#include <string>

namespace robophi {

/// How to write the replay page.
struct ReplayOptions {
  /// The page stays under this size (bytes): frames (and, if need be, plot rows)
  /// are decimated to fit, and the page says so.
  double sizeCapBytes = 50e6;
  /// Where to write; empty means `runDir/replay.html`.
  std::string outputPath;
};

/// Reads the run folder `runDir` (model.json, particles.csv, energy.csv and, when
/// present, world.json (output/world_view.h), joints.csv and contacts.csv, whose
/// columns go into the page as they are; docs/output-format.md) and writes the
/// replay page, whole or not at all; a page written into a robophi results
/// folder is added to its marker. On failure returns false, writes nothing and
/// sets `error` to a message that names the file and what is wrong.
bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options, std::string& error);

}  // namespace robophi
