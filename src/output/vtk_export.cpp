// robophi export vtk: a run folder as a ParaView time series.
//
// One ASCII PolyData file per frame (points = particles, lines = linear
// connectors) and a .pvd collection that gives each file its time. ASCII keeps
// the files readable and checkable by eye; they are for looking at, not archiving.
#include "output/vtk_export.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "output/results_folder.h"
#include "output/run_reader.h"

namespace robophi {

namespace {

namespace fs = std::filesystem;
using output::RunFolder;

std::string frameFileName(std::size_t frame) { return fmt::format("frame_{:06}.vtp", frame); }

// Velocity of every particle in frame k by finite differences of positions:
// central (x[k+1] − x[k−1]) / (t[k+1] − t[k−1]) inside, one-sided at the ends,
// zero for a single frame or frames at the same time.
std::vector<double> frameVelocity(const RunFolder& run, std::size_t k) {
  const std::size_t n = static_cast<std::size_t>(run.particleCount);
  std::vector<double> velocity(3 * n, 0.0);
  if (run.frameCount() < 2) return velocity;
  const std::size_t before = k > 0 ? k - 1 : k;
  const std::size_t after = k + 1 < run.frameCount() ? k + 1 : k;
  const double dt = run.frameTime[after] - run.frameTime[before];
  if (!(dt > 0.0)) return velocity;
  for (std::size_t i = 0; i < n; ++i) {
    const double* p0 = run.position(before, static_cast<int>(i));
    const double* p1 = run.position(after, static_cast<int>(i));
    for (std::size_t d = 0; d < 3; ++d) velocity[3 * i + d] = (p1[d] - p0[d]) / dt;
  }
  return velocity;
}

// Strain of each linear connector in frame k: (length − rest) / rest.
std::vector<double> frameStrain(const RunFolder& run, std::size_t k) {
  std::vector<double> strain;
  strain.reserve(run.linear.size());
  for (const output::LinearLink& link : run.linear) {
    const double* a = run.position(k, link.a);
    const double* b = run.position(k, link.b);
    const double length = std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    strain.push_back(link.restLength > 0.0 ? (length - link.restLength) / link.restLength : 0.0);
  }
  return strain;
}

template <typename T>
void appendValues(std::string& out, const T* values, std::size_t count, std::size_t perLine) {
  for (std::size_t i = 0; i < count; ++i) {
    out += (i % perLine == 0) ? "\n          " : " ";
    fmt::format_to(std::back_inserter(out), "{}", values[i]);
  }
  out += "\n        ";
}

template <typename T>
void appendDataArray(std::string& out, const char* type, const char* name, int components,
                     const std::vector<T>& values) {
  fmt::format_to(std::back_inserter(out),
                 "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
                 "format=\"ascii\">",
                 type, name, components);
  // Three tuples a line for vectors, eight values a line for scalars.
  const std::size_t perLine = components == 1 ? 8 : 3 * static_cast<std::size_t>(components);
  appendValues(out, values.data(), values.size(), perLine);
  out += "</DataArray>\n";
}

std::string framePolyData(const RunFolder& run, std::size_t k) {
  const std::size_t n = static_cast<std::size_t>(run.particleCount);
  const std::size_t lines = run.linear.size();
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out +=
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  fmt::format_to(std::back_inserter(out), "  <!-- robophi frame {} of {}, t = {} s -->\n", k,
                 run.frameCount(), run.frameTime[k]);
  out += "  <PolyData>\n";
  fmt::format_to(std::back_inserter(out),
                 "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" "
                 "NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
                 n, lines);
  out += "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  appendDataArray(out, "Float64", "velocity", 3, frameVelocity(run, k));
  appendDataArray(out, "Float64", "radius", 1, run.radius);
  appendDataArray(out, "Int32", "object", 1, run.object);
  appendDataArray(out, "Int32", "fixed", 1, run.fixed);
  out += "      </PointData>\n";
  out += "      <CellData Scalars=\"strain\">\n";
  appendDataArray(out, "Float64", "strain", 1, frameStrain(run, k));
  out += "      </CellData>\n";
  out += "      <Points>\n";
  const std::vector<double> points(run.position(k, 0), run.position(k, 0) + 3 * n);
  appendDataArray(out, "Float64", "position", 3, points);
  out += "      </Points>\n";
  // Lines: two point indices per connector; offsets are each cell's end.
  std::vector<std::int64_t> connectivity, offsets;
  for (std::size_t s = 0; s < lines; ++s) {
    connectivity.push_back(run.linear[s].a);
    connectivity.push_back(run.linear[s].b);
    offsets.push_back(static_cast<std::int64_t>(2 * (s + 1)));
  }
  out += "      <Lines>\n";
  appendDataArray(out, "Int64", "connectivity", 1, connectivity);
  appendDataArray(out, "Int64", "offsets", 1, offsets);
  out += "      </Lines>\n";
  out += "    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return out;
}

bool writeText(const fs::path& path, const std::string& text, std::string& error) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) {
    error = fmt::format("{}: cannot write", path.string());
    return false;
  }
  return true;
}

}  // namespace

bool writeVtkSeries(const std::string& runDir, const std::string& outDir, std::string& error) {
  RunFolder run;
  if (!output::readRunFolderWithFrames(runDir, /*needEnergy=*/false, run, error)) return false;
  // A results folder of robophi's own (docs/output-format.md): a previous
  // export's files are replaced; anything else in the folder stops the export.
  std::vector<std::string> files;
  for (std::size_t k = 0; k < run.frameCount(); ++k) files.push_back(frameFileName(k));
  files.push_back("run.pvd");
  const std::string problem = output::resultsFolderProblem(outDir, "vtk", /*force=*/false, files);
  if (!problem.empty()) {
    error = problem + ": choose another output folder, or move those away";
    return false;
  }
  std::error_code ec;
  try {
    output::removeOwnedEntries(outDir, /*removeFolder=*/false);
    fs::create_directories(outDir, ec);
    if (!ec) output::writeResultsMarker(outDir, "vtk", files);
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  if (ec) {
    error = fmt::format("{}: cannot create the folder ({})", outDir, ec.message());
    return false;
  }
  std::string collection =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (std::size_t k = 0; k < run.frameCount(); ++k) {
    if (!writeText(fs::path(outDir) / frameFileName(k), framePolyData(run, k), error)) {
      return false;
    }
    fmt::format_to(std::back_inserter(collection),
                   "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                   run.frameTime[k], frameFileName(k));
  }
  collection += "  </Collection>\n</VTKFile>\n";
  return writeText(fs::path(outDir) / "run.pvd", collection, error);
}

}  // namespace robophi
