#include "output/run_reader.h"

#include <fmt/format.h>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string_view>

namespace robophi::output {

namespace {

namespace fs = std::filesystem;

bool readWholeFile(const fs::path& path, std::string& text, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = fmt::format("{}: cannot open", path.string());
    return false;
  }
  // One read into a string of the file's size (no stream buffer grown and copied).
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(0, std::ios::beg);
  if (!in || size < 0) {
    error = fmt::format("{}: cannot be read", path.string());
    return false;
  }
  text.resize(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(text.data(), size)) {
    error = fmt::format("{}: cannot be read", path.string());
    return false;
  }
  return true;
}

// Splits one CSV line at commas; the views point into `line`.
void splitFields(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return;
    }
    fields.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

bool parseNumber(std::string_view text, double& value) {
  text = trim(text);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end && !text.empty();
}

// Integer-valued arrays in model.json (object ids, fixed flags), with a default
// when the key is absent.
bool readIntArray(const nlohmann::json& parent, const char* key, int count, int fallback,
                  std::vector<int>& out, const std::string& where, std::string& error) {
  out.assign(static_cast<std::size_t>(count), fallback);
  if (!parent.contains(key)) return true;
  const nlohmann::json& array = parent.at(key);
  if (!array.is_array() || array.size() != static_cast<std::size_t>(count)) {
    error = fmt::format("{}: particles.{} must be an array of {} numbers", where, key, count);
    return false;
  }
  for (std::size_t i = 0; i < array.size(); ++i) out[i] = array[i].get<int>();
  return true;
}

bool readModel(const fs::path& path, RunFolder& run, std::string& error) {
  std::string text;
  if (!readWholeFile(path, text, error)) return false;
  const std::string where = path.string();
  try {
    const nlohmann::json model = nlohmann::json::parse(text);
    run.name = model.value("name", std::string());
    const nlohmann::json& particles = model.at("particles");
    run.particleCount = particles.at("count").get<int>();
    if (run.particleCount < 0) {
      error = fmt::format("{}: particles.count is {}", where, run.particleCount);
      return false;
    }
    const nlohmann::json& radius = particles.at("radius");
    if (!radius.is_array() || radius.size() != static_cast<std::size_t>(run.particleCount)) {
      error = fmt::format("{}: particles.radius must be an array of {} numbers", where,
                          run.particleCount);
      return false;
    }
    run.radius = radius.get<std::vector<double>>();
    if (!readIntArray(particles, "object", run.particleCount, 0, run.object, where, error) ||
        !readIntArray(particles, "fixed", run.particleCount, 0, run.fixed, where, error)) {
      return false;
    }
    for (const nlohmann::json& o : model.value("objects", nlohmann::json::array())) {
      run.objects.push_back({o.value("name", std::string()), o.value("kind", std::string())});
    }
    const nlohmann::json connectors = model.value("connectors", nlohmann::json::object());
    for (const nlohmann::json& s : connectors.value("linear", nlohmann::json::array())) {
      LinearLink link{s.at(0).get<int>(), s.at(1).get<int>(), s.at(2).get<double>()};
      if (link.a < 0 || link.b < 0 || link.a >= run.particleCount || link.b >= run.particleCount) {
        error = fmt::format("{}: linear connector [{}, {}] names a particle outside 0..{}", where,
                            link.a, link.b, run.particleCount - 1);
        return false;
      }
      run.linear.push_back(link);
    }
    for (const nlohmann::json& j : model.value("joints", nlohmann::json::array())) {
      run.jointNames.push_back(j.value("name", std::string()));
      run.jointKinds.push_back(j.value("kind", std::string("revolute")));
    }
    if (model.contains("gravity")) {
      for (std::size_t d = 0; d < 3; ++d) run.gravity[d] = model.at("gravity").at(d).get<double>();
    }
  } catch (const nlohmann::json::exception& e) {
    error = fmt::format("{}: {}", where, e.what());
    return false;
  }
  return true;
}

}  // namespace

std::vector<std::string> csvHeaderColumns(std::string_view line) {
  std::vector<std::string_view> fields;
  splitFields(trim(line), fields);
  std::vector<std::string> columns;
  columns.reserve(fields.size());
  for (std::string_view f : fields) columns.emplace_back(trim(f));
  return columns;
}

bool readRunModel(const std::string& runDir, RunFolder& run, std::string& error) {
  run = RunFolder{};
  return readModel(fs::path(runDir) / "model.json", run, error);
}

std::size_t CsvTable::columnIndex(const std::string& name) const {
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (columns[c] == name) return c;
  }
  return columns.size();
}

bool readCsvTable(const std::string& path, const std::vector<std::string>& requiredColumns,
                  CsvTable& table, std::string& error) {
  std::string text;
  if (!readWholeFile(path, text, error)) return false;
  table = CsvTable{};
  std::vector<std::string_view> fields;
  std::size_t lineNumber = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line = trim(std::string_view(text).substr(start, end - start));
    start = end + 1;
    ++lineNumber;
    if (line.empty()) continue;
    if (table.columns.empty()) {
      table.columns = csvHeaderColumns(line);
      continue;
    }
    splitFields(line, fields);
    if (fields.size() != table.columns.size()) {
      error = fmt::format("{}:{}: expected {} values (one per header column), found {}", path,
                          lineNumber, table.columns.size(), fields.size());
      return false;
    }
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double value = 0.0;
      if (!parseNumber(fields[c], value)) {
        error = fmt::format("{}:{}: column '{}' holds '{}', not a number", path, lineNumber,
                            table.columns[c], trim(fields[c]));
        return false;
      }
      table.values.push_back(value);
    }
    ++table.rowCount;
  }
  if (table.columns.empty()) {
    error = fmt::format("{}: empty file, expected a header line", path);
    return false;
  }
  for (const std::string& name : requiredColumns) {
    if (table.columnIndex(name) == table.columns.size()) {
      error = fmt::format("{}:1: missing column '{}'", path, name);
      return false;
    }
  }
  return true;
}

bool readRunFolder(const std::string& runDir, bool needEnergy, RunFolder& run, std::string& error) {
  const fs::path dir(runDir);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    error = fmt::format("{}: not a run folder (no such directory)", runDir);
    return false;
  }
  run = RunFolder{};
  if (!readModel(dir / "model.json", run, error)) return false;

  // particles.csv: t, then per particle x,y,z,vx,vy,vz (or x,y,z alone, the
  // format before velocities were written).
  CsvTable particles;
  const std::string particlesPath = (dir / "particles.csv").string();
  if (!readCsvTable(particlesPath, {"t"}, particles, error)) return false;
  const auto n = static_cast<std::size_t>(run.particleCount);
  const std::size_t stride = particles.columns.size() == 1 + 6 * n ? 6 : 3;
  const std::size_t expected = 1 + stride * n;
  bool layout = particles.columns.size() == expected && particles.columns[0] == "t";
  for (std::size_t i = 0; layout && i < n; ++i)
    layout = particles.columns[1 + stride * i] == fmt::format("x{}", i);
  if (!layout) {
    error = fmt::format(
        "{}:1: expected {} columns (t, then x,y,z,vx,vy,vz of the {} particles in model.json), "
        "found {}",
        particlesPath, 1 + 6 * n, run.particleCount, particles.columns.size());
    return false;
  }
  run.hasVelocities = stride == 6;
  run.frameTime.reserve(particles.rowCount);
  run.framePosition.reserve(particles.rowCount * 3 * n);
  if (run.hasVelocities) run.frameVelocity.reserve(particles.rowCount * 3 * n);
  for (std::size_t k = 0; k < particles.rowCount; ++k) {
    run.frameTime.push_back(particles.at(k, 0));
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t c = 0; c < 3; ++c)
        run.framePosition.push_back(particles.at(k, 1 + stride * i + c));
      if (run.hasVelocities)
        for (std::size_t c = 3; c < 6; ++c)
          run.frameVelocity.push_back(particles.at(k, 1 + stride * i + c));
    }
  }

  const fs::path energyPath = dir / "energy.csv";
  if (needEnergy || fs::exists(energyPath, ec)) {
    if (!readCsvTable(energyPath.string(),
                      {"t", "dt", "kinetic", "potential", "dissipated", "total"}, run.energy,
                      error)) {
      return false;
    }
  }
  const fs::path jointsPath = dir / "joints.csv";
  if (fs::exists(jointsPath, ec)) {
    if (!readCsvTable(jointsPath.string(), {"t"}, run.joints, error)) return false;
    run.hasJoints = true;
  }
  const fs::path contactsPath = dir / "contacts.csv";
  if (fs::exists(contactsPath, ec)) {
    if (!readCsvTable(contactsPath.string(), {"t", "a", "b", "fx", "fy", "fz"}, run.contacts,
                      error)) {
      return false;
    }
    run.hasContacts = true;
  }
  return true;
}

bool readRunFolderWithFrames(const std::string& runDir, bool needEnergy, RunFolder& run,
                             std::string& error) {
  if (!readRunFolder(runDir, needEnergy, run, error)) return false;
  if (run.frameCount() == 0) {
    error = fmt::format("{}: no frames (only a header line)",
                        (fs::path(runDir) / "particles.csv").string());
    return false;
  }
  return true;
}

}  // namespace robophi::output
