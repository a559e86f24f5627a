#pragma once
/// \file
/// ParaView export of a run: one VTK PolyData file (.vtp, ASCII) per frame and a
/// .pvd collection that indexes them by time. docs/viewer.md describes the files.

#include <string>

namespace robophi {

/// Reads the run folder `runDir` (model.json, particles.csv) and writes into
/// `outDir` (created if needed; it must be absent, empty or a previous export's,
/// whose files are replaced: output/results_folder.h):
///  - `frame_NNNNNN.vtp`: the particles as points with point data `velocity`
///    (m/s, finite differences between frames: central inside, one-sided at the
///    ends), `radius` (m), `object` and `fixed`; the linear connectors as lines
///    with cell data `strain` = (length − rest)/rest;
///  - `run.pvd`: the collection, one DataSet per frame with its time (s);
///  - the marker `robophi-results.json` (kind "vtk"), written first.
/// On failure returns false and sets `error` to a message naming the file and
/// what is wrong.
bool writeVtkSeries(const std::string& runDir, const std::string& outDir, std::string& error);

}  // namespace robophi
