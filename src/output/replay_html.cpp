// robophi export html: the run folder as one self-contained replay page.
//
// The page is viewer/replay.html.in with three.js, the viewer's CSS and JS
// already inlined at build time (robophi/replay_assets.h); this file adds the run
// data as one JSON object between kPageHead and kPageTail. The model's numbers
// are JSON numbers; the series are binary (base64 of little-endian numbers,
// docs/viewer.md): the times of frames and rows as the doubles of the CSV
// files, everything the page draws (positions, plotted values, contact forces)
// in single precision, as the viewer draws it (a page a third the size of one
// in decimal text, and read without parsing). Frames are decimated by a stride
// so the page stays under the cap.
#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "output/base64.h"
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

// Column `first` to `first + count` of the kept rows of `values` (rows of
// `width`), row-major, non-finite numbers in one form (a page made from the
// run's rows and one made from its files are the same bytes whatever NaN the
// run produced).
template <class Out, class In>
std::vector<Out> keptValues(const In* values, std::size_t width, std::size_t first,
                            std::size_t count, const std::vector<std::size_t>& kept) {
  std::vector<Out> out;
  out.reserve(kept.size() * count);
  for (std::size_t r : kept) {
    for (std::size_t c = first; c < first + count; ++c) {
      const In v = values[r * width + c];
      out.push_back(std::isnan(v) ? std::numeric_limits<Out>::quiet_NaN() : static_cast<Out>(v));
    }
  }
  return out;
}

// "name":"<base64 of the numbers' little-endian bytes>".
template <class T>
void appendBinary(std::string& out, const char* name, const std::vector<T>& numbers) {
  static_assert(std::endian::native == std::endian::little,
                "the page's numbers are little-endian: swap bytes on this machine");
  fmt::format_to(std::back_inserter(out), ",\"{}\":\"", name);
  output::appendBase64(out, numbers.data(), numbers.size() * sizeof(T));
  out += '"';
}

// How many rows keptIndices keeps.
std::size_t keptCount(std::size_t count, std::size_t stride) {
  if (count == 0) return 0;
  return (count - 1) / stride + 1 + ((count - 1) % stride != 0 ? 1 : 0);
}

// The page's bytes for `count` rows of `width` numbers of `size` bytes each.
std::size_t encodedBytes(std::size_t count, std::size_t width, std::size_t size) {
  return output::base64Size(count * width * size) + 16;  // "name":"...", and the count
}

// A table's kept rows: their times (the first column) as doubles, the rest as floats.
std::size_t seriesBytes(const ReplaySeries& series, std::size_t stride) {
  const std::size_t kept = keptCount(series.rows(), stride);
  const std::size_t width = series.columns.size();
  return width == 0 ? 0
                    : encodedBytes(kept, 1, sizeof(double)) +
                          encodedBytes(kept, width - 1, sizeof(float));
}

// ,"t":"<the kept rows' times, float64>","values":"<their other numbers, float32>".
void appendRows(std::string& out, const ReplaySeries& series, const std::vector<std::size_t>& kept) {
  const std::size_t width = series.columns.size();
  if (width == 0) return;
  appendBinary(out, "t", keptValues<double>(series.values.data(), width, 0, 1, kept));
  appendBinary(out, "values", keptValues<float>(series.values.data(), width, 1, width - 1, kept));
}

std::size_t frameBytes(const ReplayRows& rows, std::size_t particles, std::size_t stride) {
  const std::size_t kept = keptCount(rows.frameTime.size(), stride);
  return encodedBytes(kept, 1, sizeof(double)) + encodedBytes(kept, 3 * particles, sizeof(float));
}

// The smallest stride whose kept rows (`bytes(stride)`) fit in `budget` bytes
// (`count` if none does).
template <class Bytes>
std::size_t strideToFit(std::size_t count, const Bytes& bytes, std::size_t budget) {
  const std::size_t total = bytes(1);
  if (total <= budget || count <= 1) return 1;
  std::size_t stride = std::max<std::size_t>(1, total / std::max<std::size_t>(budget, 1));
  while (stride < count && bytes(stride) > budget) stride = std::max(stride + 1, stride + stride / 8);
  return std::min(stride, count);
}

void appendColumns(std::string& out, const char* name, const ReplaySeries& series) {
  fmt::format_to(std::back_inserter(out), ",\"{}\":{{\"columns\":[", name);
  for (std::size_t c = 0; c < series.columns.size(); ++c) {
    if (c > 0) out += ',';
    out += jsonString(series.columns[c]);
  }
  out += ']';
}

// A decimated table: "name":{"columns":[..],"sourceRows":R,"stride":s,"count":K,"t":..,"values":..}.
void appendTable(std::string& out, const char* name, const ReplaySeries& series,
                 std::size_t stride) {
  appendColumns(out, name, series);
  const std::vector<std::size_t> kept = keptIndices(series.rows(), stride);
  fmt::format_to(std::back_inserter(out), ",\"sourceRows\":{},\"stride\":{},\"count\":{}",
                 series.rows(), stride, kept.size());
  appendRows(out, series, kept);
  out += '}';
}

// Contacts are decimated by time groups (a row's t is its first number), so a
// kept time keeps all its contacts.
void appendContacts(std::string& out, const ReplaySeries& series, std::size_t stride) {
  const std::size_t width = series.columns.size();
  const std::size_t rows = series.rows();
  std::vector<std::size_t> groupStart;
  for (std::size_t r = 0; r < rows; ++r) {
    if (r == 0 || series.values[r * width] != series.values[(r - 1) * width]) groupStart.push_back(r);
  }
  std::vector<std::size_t> kept;
  for (std::size_t g : keptIndices(groupStart.size(), stride)) {
    const std::size_t end = g + 1 < groupStart.size() ? groupStart[g + 1] : rows;
    for (std::size_t r = groupStart[g]; r < end; ++r) kept.push_back(r);
  }
  appendColumns(out, "contacts", series);
  fmt::format_to(std::back_inserter(out),
                 ",\"sourceRows\":{},\"sourceTimes\":{},\"stride\":{},\"count\":{}", rows,
                 groupStart.size(), stride, kept.size());
  appendRows(out, series, kept);
  out += '}';
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
  const auto particles = static_cast<std::size_t>(run.particleCount);
  if (rows.framePosition.size() != rows.frameTime.size() * 3 * particles) {
    error = fmt::format("{}: {} positions for {} frames of {} particles", runDir,
                        rows.framePosition.size(), rows.frameTime.size(), particles);
    return false;
  }

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
  const std::size_t allSeriesBytes =
      seriesBytes(rows.energy, 1) + seriesBytes(rows.joints, 1) + seriesBytes(rows.contacts, 1);
  const auto framesAt = [&](std::size_t stride) { return frameBytes(rows, particles, stride); };
  std::size_t frameStride = 1;
  double seriesShare = 1.0;  // fraction of each plot table kept
  if (framesAt(1) + allSeriesBytes > available) {
    const std::size_t seriesBudget = std::min(allSeriesBytes, available / 4);
    seriesShare = allSeriesBytes > 0 ? static_cast<double>(seriesBudget) /
                                           static_cast<double>(allSeriesBytes)
                                     : 1.0;
    frameStride = strideToFit(rows.frameTime.size(), framesAt, available - seriesBudget);
  }
  auto seriesStride = [&](const ReplaySeries& series) {
    if (seriesShare >= 1.0) return std::size_t{1};
    const auto bytesAt = [&](std::size_t stride) { return seriesBytes(series, stride); };
    return strideToFit(series.rows(), bytesAt,
                       static_cast<std::size_t>(seriesShare * static_cast<double>(bytesAt(1))));
  };
  const std::size_t energyStride = seriesStride(rows.energy);
  const std::size_t jointsStride = seriesStride(rows.joints);
  const std::size_t contactsStride = seriesStride(rows.contacts);

  // The data object, in the order viewer/replay.js reads it.
  std::string data = "{" + model;
  data.reserve(data.size() + framesAt(frameStride) + seriesBytes(rows.energy, energyStride) +
               seriesBytes(rows.joints, jointsStride) +
               seriesBytes(rows.contacts, contactsStride) + 4096);
  fmt::format_to(std::back_inserter(data), ",\"threeVersion\":\"{}\",\"sizeCapBytes\":{}",
                 replay_assets::kThreeVersion, cap);
  const std::vector<std::size_t> keptFrames = keptIndices(rows.frameTime.size(), frameStride);
  fmt::format_to(std::back_inserter(data),
                 ",\"frames\":{{\"sourceCount\":{},\"stride\":{},\"count\":{}",
                 rows.frameTime.size(), frameStride, keptFrames.size());
  appendBinary(data, "t", keptValues<double>(rows.frameTime.data(), 1, 0, 1, keptFrames));
  appendBinary(data, "position",
               keptValues<float>(rows.framePosition.data(), 3 * particles, 0, 3 * particles,
                                 keptFrames));
  data += '}';
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
  if (rows.hasContacts) appendContacts(data, rows.contacts, contactsStride);
  data += '}';

  const std::size_t pageBytes =
      piecesSize(replay_assets::kPageHead) + data.size() + piecesSize(replay_assets::kPageTail);
  if (static_cast<double>(pageBytes) > cap) {
    error = fmt::format(
        "{}: the page would be {} bytes, over the cap of {} bytes even with {} of "
        "{} frames; raise the cap",
        outPath.string(), pageBytes, cap, keptFrames.size(), rows.frameTime.size());
    return false;
  }
  return writePage(outPath, data, error);
}

}  // namespace

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options, std::string& error) {
  RunFolder run;
  if (!output::readRunFolderWithFrames(runDir, /*needEnergy=*/true, run, error)) return false;
  ReplayRows rows;
  rows.frameTime = run.frameTime;
  rows.framePosition.reserve(run.framePosition.size());
  for (double x : run.framePosition) rows.framePosition.push_back(static_cast<float>(x));
  const auto series = [](CsvTable& table) { return ReplaySeries{table.columns, std::move(table.values)}; };
  rows.energy = series(run.energy);
  rows.joints = series(run.joints);
  rows.contacts = series(run.contacts);
  rows.hasJoints = run.hasJoints;
  rows.hasContacts = run.hasContacts;
  return writePageFrom(runDir, options, run, rows, error);
}

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options,
                     const ReplayRows& rows, std::string& error) {
  // No frame: the files' own path says what is missing.
  if (rows.frameTime.empty()) return writeReplayHtml(runDir, options, error);
  RunFolder run;
  if (!output::readRunModel(runDir, run, error)) return false;
  return writePageFrom(runDir, options, run, rows, error);
}

}  // namespace robophi
