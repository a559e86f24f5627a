// robophi export html: the run folder as one self-contained replay page.
//
// The page is viewer/replay.html.in with three.js, the viewer's CSS and JS
// already inlined at build time (robophi/replay_assets.h); this file adds the run
// data as one JSON object between kPageHead and kPageTail. Numbers are written in
// their shortest round-trip form, so the page shows the very positions of
// particles.csv. Frames are decimated by a stride so the page stays under the cap.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "output/json_numbers.h"
#include "output/replay.h"
#include "output/results_folder.h"
#include "output/run_reader.h"
#include "output/world_view.h"
#include "robophi/replay_assets.h"

namespace robophi {

namespace {

namespace fs = std::filesystem;
using output::CsvTable;
using output::RunFolder;

// Room kept for the JSON punctuation and notices that the estimates below leave out.
constexpr std::size_t kSlackBytes = 4096;

template <std::size_t N>
std::size_t piecesSize(const std::string_view (&pieces)[N]) {
  std::size_t size = 0;
  for (std::string_view piece : pieces) size += piece.size();
  return size;
}

// JSON has no NaN or infinity: a diverged run's values become null.
void appendNumber(std::string& out, double value) {
  if (std::isfinite(value)) {
    output::appendShortest(out, value);
  } else {
    out += "null";
  }
}

// A JSON string that is also safe inside <script>: "</" would end the element.
std::string jsonString(const std::string& text) {
  std::string quoted = nlohmann::json(text).dump();
  std::string safe;
  safe.reserve(quoted.size());
  for (std::size_t i = 0; i < quoted.size(); ++i) {
    if (quoted[i] == '<' && i + 1 < quoted.size() && quoted[i + 1] == '/') {
      safe += "<\\";
    } else {
      safe += quoted[i];
    }
  }
  return safe;
}

// Indices 0, stride, 2·stride, ... and always the last one.
std::vector<std::size_t> keptIndices(std::size_t count, std::size_t stride) {
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < count; i += stride) kept.push_back(i);
  if (count > 0 && kept.back() != count - 1) kept.push_back(count - 1);
  return kept;
}

// The model part of the data: what does not change over the run.
std::string modelJson(const RunFolder& run) {
  std::string out;
  out += "\"name\":" + jsonString(run.name);
  fmt::format_to(std::back_inserter(out), ",\"particles\":{{\"count\":{},\"radius\":[",
                 run.particleCount);
  for (std::size_t i = 0; i < run.radius.size(); ++i) {
    if (i > 0) out += ',';
    appendNumber(out, run.radius[i]);
  }
  fmt::format_to(std::back_inserter(out), "],\"object\":[{}],\"fixed\":[{}]}}",
                 fmt::join(run.object, ","), fmt::join(run.fixed, ","));
  out += ",\"objects\":[";
  for (std::size_t o = 0; o < run.objects.size(); ++o) {
    if (o > 0) out += ',';
    out += "{\"name\":" + jsonString(run.objects[o].name) +
           ",\"kind\":" + jsonString(run.objects[o].kind) + "}";
  }
  out += "],\"linear\":[";
  for (std::size_t s = 0; s < run.linear.size(); ++s) {
    if (s > 0) out += ',';
    fmt::format_to(std::back_inserter(out), "{},{},", run.linear[s].a, run.linear[s].b);
    appendNumber(out, run.linear[s].restLength);
  }
  out += "],\"gravity\":[";
  for (int d = 0; d < 3; ++d) {
    if (d > 0) out += ',';
    appendNumber(out, run.gravity[d]);
  }
  out += ']';
  return out;
}

// "[row]" appended in place.
void appendBracketed(std::string& out, const std::string& row) {
  out += '[';
  out += row;
  out += ']';
}

// Rows of a table rendered one string per row ("v0,v1,..."), for sizing and writing.
std::vector<std::string> renderRows(const CsvTable& table) {
  std::vector<std::string> rows(table.rowCount);
  for (std::size_t r = 0; r < table.rowCount; ++r) {
    for (std::size_t c = 0; c < table.columns.size(); ++c) {
      if (c > 0) rows[r] += ',';
      appendNumber(rows[r], table.at(r, c));
    }
  }
  return rows;
}

std::vector<std::string> renderFrames(const RunFolder& run) {
  std::vector<std::string> frames(run.frameCount());
  const std::size_t valuesPerFrame = 3 * static_cast<std::size_t>(run.particleCount);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    appendNumber(frames[k], run.frameTime[k]);
    for (std::size_t v = 0; v < valuesPerFrame; ++v) {
      frames[k] += ',';
      appendNumber(frames[k], run.framePosition[k * valuesPerFrame + v]);
    }
  }
  return frames;
}

std::size_t keptBytes(const std::vector<std::string>& rows, std::size_t stride) {
  std::size_t bytes = 0;
  for (std::size_t i : keptIndices(rows.size(), stride)) bytes += rows[i].size() + 3;  // "[row],"
  return bytes;
}

// The smallest stride whose kept rows fit in `budget` bytes (rows.size() if none does).
std::size_t strideToFit(const std::vector<std::string>& rows, std::size_t budget) {
  std::size_t total = keptBytes(rows, 1);
  if (total <= budget || rows.size() <= 1) return 1;
  std::size_t stride = std::max<std::size_t>(1, total / std::max<std::size_t>(budget, 1));
  while (stride < rows.size() && keptBytes(rows, stride) > budget) {
    stride = std::max(stride + 1, stride + stride / 8);
  }
  return std::min(stride, rows.size());
}

// A decimated table: "name":{"columns":[..],"sourceRows":R,"stride":s,"rows":[[..],..]}.
void appendTable(std::string& out, const char* name, const ReplaySeries& series,
                 std::size_t stride) {
  fmt::format_to(std::back_inserter(out), ",\"{}\":{{\"columns\":[", name);
  for (std::size_t c = 0; c < series.columns.size(); ++c) {
    if (c > 0) out += ',';
    out += jsonString(series.columns[c]);
  }
  fmt::format_to(std::back_inserter(out), "],\"sourceRows\":{},\"stride\":{},\"rows\":[",
                 series.rows.size(), stride);
  bool first = true;
  for (std::size_t i : keptIndices(series.rows.size(), stride)) {
    if (!first) out += ',';
    first = false;
    appendBracketed(out, series.rows[i]);
  }
  out += "]}";
}

// Contacts are decimated by time groups (`times`: each row's t), so a kept time
// keeps all its contacts.
void appendContacts(std::string& out, const ReplaySeries& series, const std::vector<double>& times,
                    std::size_t stride) {
  const std::vector<std::string>& rows = series.rows;
  std::vector<std::size_t> groupStart;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (r == 0 || times[r] != times[r - 1]) groupStart.push_back(r);
  }
  out += ",\"contacts\":{\"columns\":[";
  for (std::size_t c = 0; c < series.columns.size(); ++c) {
    if (c > 0) out += ',';
    out += jsonString(series.columns[c]);
  }
  fmt::format_to(std::back_inserter(out),
                 "],\"sourceRows\":{},\"sourceTimes\":{},\"stride\":{},\"rows\":[", rows.size(),
                 groupStart.size(), stride);
  bool first = true;
  for (std::size_t g : keptIndices(groupStart.size(), stride)) {
    const std::size_t end = g + 1 < groupStart.size() ? groupStart[g + 1] : rows.size();
    for (std::size_t r = groupStart[g]; r < end; ++r) {
      if (!first) out += ',';
      first = false;
      appendBracketed(out, rows[r]);
    }
  }
  out += "]}";
}

// The page (head, data, tail) written whole or not at all; a page written into
// a robophi run folder is listed in its marker.
// world.json (output/world_view.h) as compact JSON safe inside <script>, or
// empty when the run folder has none (an older run, a hand-made folder). A
// file that is there but not JSON is an error naming it.
bool readWorldView(const fs::path& dir, std::string& world, std::string& error) {
  const fs::path path = dir / std::string(output::kWorldViewFile);
  std::error_code ec;
  if (!fs::exists(path, ec)) return true;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = fmt::format("{}: cannot be read", path.string());
    return false;
  }
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (!j.is_object()) {
      error = fmt::format("{}: expected a JSON object", path.string());
      return false;
    }
    const std::string compact = j.dump();
    world.clear();
    for (std::size_t i = 0; i < compact.size(); ++i) {  // "</" would end the <script> element
      if (compact[i] == '<' && i + 1 < compact.size() && compact[i + 1] == '/') {
        world += "<\\";
      } else {
        world += compact[i];
      }
    }
  } catch (const nlohmann::json::exception& e) {
    error = fmt::format("{}: not valid JSON: {}", path.string(), e.what());
    return false;
  }
  return true;
}

bool writePage(const fs::path& path, const std::string& data, std::string& error) {
  try {
    output::writeFileAtomically(path, [&](std::ostream& out) {
      for (std::string_view piece : replay_assets::kPageHead) out << piece;
      out << data;
      for (std::string_view piece : replay_assets::kPageTail) out << piece;
    });
    if (path.has_parent_path())
      output::addToResultsMarker(path.parent_path(), path.filename().string());
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  return true;
}

// The page of the run in `runDir` from its model (`run`: model.json's fields)
// and its series as rows.
bool writePageFrom(const std::string& runDir, const ReplayOptions& options, const RunFolder& run,
                   const ReplayRows& rows, std::string& error) {
  const fs::path outPath =
      options.outputPath.empty() ? fs::path(runDir) / "replay.html" : fs::path(options.outputPath);

  std::string world;
  if (!readWorldView(fs::path(runDir), world, error)) return false;
  std::string model = modelJson(run);
  if (!world.empty()) model += ",\"world\":" + world;
  const std::vector<std::string>& frames = rows.frames;
  const std::vector<std::string>& energy = rows.energy.rows;
  const std::vector<std::string>& joints = rows.joints.rows;
  const std::vector<std::string>& contacts = rows.contacts.rows;

  // Budget: the cap less the page itself and the model; plot rows may take up to
  // a quarter of what is left, frames the rest.
  const std::size_t fixedBytes = piecesSize(replay_assets::kPageHead) +
                                 piecesSize(replay_assets::kPageTail) + model.size() + kSlackBytes;
  const double cap = options.sizeCapBytes;
  if (!(cap > static_cast<double>(fixedBytes))) {
    error = fmt::format("size cap {} bytes is smaller than the page without frames ({} bytes)", cap,
                        fixedBytes);
    return false;
  }
  const auto available = static_cast<std::size_t>(cap) - fixedBytes;
  const std::size_t seriesBytes =
      keptBytes(energy, 1) + keptBytes(joints, 1) + keptBytes(contacts, 1);
  const std::size_t frameBytes = keptBytes(frames, 1);
  std::size_t frameStride = 1;
  double seriesShare = 1.0;  // fraction of each plot table kept
  if (frameBytes + seriesBytes > available) {
    const std::size_t seriesBudget = std::min(seriesBytes, available / 4);
    seriesShare = seriesBytes > 0
                      ? static_cast<double>(seriesBudget) / static_cast<double>(seriesBytes)
                      : 1.0;
    frameStride = strideToFit(frames, available - seriesBudget);
  }
  auto seriesStride = [&](const std::vector<std::string>& series) {
    return seriesShare >= 1.0
               ? std::size_t{1}
               : strideToFit(series, static_cast<std::size_t>(
                                         seriesShare * static_cast<double>(keptBytes(series, 1))));
  };
  const std::size_t energyStride = seriesStride(energy);
  const std::size_t jointsStride = seriesStride(joints);
  const std::size_t contactsStride = seriesStride(contacts);

  // The data object, in the order viewer/replay.js reads it.
  std::string data = "{" + model;
  data.reserve(data.size() + keptBytes(frames, frameStride) + keptBytes(energy, energyStride) +
               keptBytes(joints, jointsStride) + keptBytes(contacts, contactsStride) + 4096);
  fmt::format_to(std::back_inserter(data), ",\"threeVersion\":\"{}\",\"sizeCapBytes\":{}",
                 replay_assets::kThreeVersion, cap);
  const std::vector<std::size_t> keptFrames = keptIndices(frames.size(), frameStride);
  fmt::format_to(std::back_inserter(data),
                 ",\"frames\":{{\"sourceCount\":{},\"stride\":{},\"rows\":[", frames.size(),
                 frameStride);
  for (std::size_t i = 0; i < keptFrames.size(); ++i) {
    if (i > 0) data += ',';
    appendBracketed(data, frames[keptFrames[i]]);
  }
  data += "]}";
  appendTable(data, "energy", rows.energy, energyStride);
  if (rows.hasJoints) {
    appendTable(data, "joints", rows.joints, jointsStride);
    data += ",\"jointKinds\":[";
    for (std::size_t j = 0; j < run.jointKinds.size(); ++j) {
      if (j > 0) data += ',';
      data += jsonString(run.jointKinds[j]);
    }
    data += ']';
  }
  if (rows.hasContacts) appendContacts(data, rows.contacts, rows.contactTimes, contactsStride);
  data += '}';

  const std::size_t pageBytes =
      piecesSize(replay_assets::kPageHead) + data.size() + piecesSize(replay_assets::kPageTail);
  if (static_cast<double>(pageBytes) > cap) {
    error = fmt::format(
        "{}: the page would be {} bytes, over the cap of {} bytes even with {} of "
        "{} frames; raise the cap",
        outPath.string(), pageBytes, cap, keptFrames.size(), frames.size());
    return false;
  }
  return writePage(outPath, data, error);
}

}  // namespace

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options, std::string& error) {
  RunFolder run;
  if (!output::readRunFolderWithFrames(runDir, /*needEnergy=*/true, run, error)) return false;
  ReplayRows rows;
  rows.frames = renderFrames(run);
  rows.energy = {run.energy.columns, renderRows(run.energy)};
  rows.joints = {run.joints.columns, renderRows(run.joints)};
  rows.contacts = {run.contacts.columns, renderRows(run.contacts)};
  rows.contactTimes.reserve(run.contacts.rowCount);
  for (std::size_t r = 0; r < run.contacts.rowCount; ++r)
    rows.contactTimes.push_back(run.contacts.at(r, 0));
  rows.hasJoints = run.hasJoints;
  rows.hasContacts = run.hasContacts;
  return writePageFrom(runDir, options, run, rows, error);
}

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options,
                     const ReplayRows& rows, std::string& error) {
  // No frame: the files' own path says what is missing.
  if (rows.frames.empty()) return writeReplayHtml(runDir, options, error);
  RunFolder run;
  if (!output::readRunModel(runDir, run, error)) return false;
  return writePageFrom(runDir, options, run, rows, error);
}

}  // namespace robophi
