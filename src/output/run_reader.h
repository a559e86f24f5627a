#pragma once
/// \file
/// Reading a run folder back (docs/output-format.md), for the exporters:
/// `robophi export html` and `robophi export vtk`.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace robophi::output {

/// A CSV file with a header line and numeric rows.
struct CsvTable {
  std::vector<std::string> columns;
  /// Row-major values (rowCount × columns.size()).
  std::vector<double> values;
  std::size_t rowCount = 0;

  double at(std::size_t row, std::size_t column) const {
    return values[row * columns.size() + column];
  }
  /// Index of a column by name, or columns.size() when absent.
  std::size_t columnIndex(const std::string& name) const;
};

/// A linear spring as model.json lists it.
struct LinearLink {
  int a = 0;
  int b = 0;
  double restLength = 0.0;  // (m)
};

/// An object's name and kind, for colouring and legends.
struct ObjectLabel {
  std::string name;
  std::string kind;
};

/// What a run folder holds, as read from its files.
struct RunFolder {
  std::string name;  // the model's name
  int particleCount = 0;
  std::vector<double> radius;  // (particleCount) m
  std::vector<int> object;     // (particleCount) index into objects
  std::vector<int> fixed;      // (particleCount) 1 for fixed particles
  std::vector<ObjectLabel> objects;
  std::vector<LinearLink> linear;
  std::vector<std::string> jointNames;
  std::vector<std::string> jointKinds;    // "revolute" (rad) or "prismatic" (m)
  double gravity[3] = {0.0, 0.0, -9.81};  // (m/s²)

  /// particles.csv: frameTime (frameCount) s, framePosition (frameCount × particleCount × 3) m.
  std::vector<double> frameTime;
  std::vector<double> framePosition;
  /// Velocities in the same layout (m/s), when particles.csv has them (hasVelocities).
  bool hasVelocities = false;
  std::vector<double> frameVelocity;
  CsvTable energy;  // t,dt,kinetic,potential,dissipated,[external,]total
  bool hasJoints = false;
  CsvTable joints;  // t,<name>,...
  bool hasContacts = false;
  CsvTable contacts;  // t,a,b,fx,fy,fz[,tx,ty,tz,sliding]: normal, friction force

  std::size_t frameCount() const { return frameTime.size(); }
  /// Position of particle i in frame k, as a pointer to its x, y, z.
  const double* position(std::size_t frame, int particle) const {
    return &framePosition[(frame * static_cast<std::size_t>(particleCount) +
                           static_cast<std::size_t>(particle)) *
                          3];
  }
};

/// The column names of a CSV header line, as readCsvTable takes them (split at
/// commas, blanks trimmed).
std::vector<std::string> csvHeaderColumns(std::string_view line);

/// Reads model.json alone (the model's fields of `run`); on failure returns false
/// and sets `error` naming the file.
bool readRunModel(const std::string& runDir, RunFolder& run, std::string& error);

/// Reads model.json and particles.csv (required), energy.csv (required when
/// `needEnergy`), joints.csv and contacts.csv (when present). On failure returns
/// false and sets `error` to a message naming the file, the line and what is wrong.
bool readRunFolder(const std::string& runDir, bool needEnergy, RunFolder& run, std::string& error);
/// The same, and particles.csv must hold at least one frame (what the exporters need).
bool readRunFolderWithFrames(const std::string& runDir, bool needEnergy, RunFolder& run,
                             std::string& error);

/// Reads a CSV file of numbers with a header line; `requiredColumns` must all be
/// present. On failure returns false with a message naming the file and line.
bool readCsvTable(const std::string& path, const std::vector<std::string>& requiredColumns,
                  CsvTable& table, std::string& error);

}  // namespace robophi::output
