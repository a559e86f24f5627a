// robophi export html: the run folder as one self-contained replay page.
//
// The page is viewer/replay.html.in with three.js, the viewer's CSS and JS
// already inlined at build time (robophi/replay_assets.h); this file adds the
// run's series between kPageHead and kPageMiddle, as pieces (SeriesPieces) that a
// run writes as it goes (ReplayPageStream), and the run's data object (the model,
// what each series holds) between kPageMiddle and kPageTail. The model's numbers
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
#include "output/replay_meshes.h"
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

// JSON text made safe inside <script>: "</" would end the element ("<\\/" is
// the same JSON).
std::string scriptSafe(const std::string& json) {
  std::string safe;
  safe.reserve(json.size());
  for (std::size_t i = 0; i < json.size(); ++i) {
    if (json[i] == '<' && i + 1 < json.size() && json[i + 1] == '/') {
      safe += "<\\";
    } else {
      safe += json[i];
    }
  }
  return safe;
}

// A JSON string that is also safe inside <script>.
std::string jsonString(const std::string& text) { return scriptSafe(nlohmann::json(text).dump()); }

// Writes the page's fixed pieces (replay_assets) to `out`.
template <std::size_t N>
void writePieces(std::ostream& out, const std::string_view (&pieces)[N]) {
  for (std::string_view piece : pieces) out << piece;
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
    world = scriptSafe(j.dump());
  } catch (const nlohmann::json::exception& e) {
    error = fmt::format("{}: not valid JSON: {}", path.string(), e.what());
    return false;
  }
  return true;
}

// The kept rows of a series, as row indices: `rows` (null: every row, 0 to
// count - 1) and how many.
struct Kept {
  const std::vector<std::size_t>* rows = nullptr;
  std::size_t count = 0;
  std::size_t operator[](std::size_t k) const { return rows != nullptr ? (*rows)[k] : k; }
};

// Column `first` to `first + count` of the kept rows `from` to `to` of `values`
// (rows of `width`), row-major, non-finite numbers in one form (a page made
// from the run's rows and one made from its files are the same bytes whatever
// NaN the run produced).
template <class Out, class In>
std::vector<Out> keptValues(const In* values, std::size_t width, std::size_t first,
                            std::size_t count, const Kept& kept, std::size_t from, std::size_t to) {
  std::vector<Out> out;
  out.reserve((to - from) * count);
  for (std::size_t k = from; k < to; ++k) {
    const std::size_t r = kept[k];
    for (std::size_t c = first; c < first + count; ++c) {
      const In v = values[r * width + c];
      out.push_back(std::isnan(v) ? std::numeric_limits<Out>::quiet_NaN() : static_cast<Out>(v));
    }
  }
  return out;
}

// One piece of a series: <script data-series="name"> holding the base64 of the
// numbers' little-endian bytes; none for no numbers.
constexpr std::string_view kPieceOpen =
    "<script type=\"application/x-robophi-series\" data-series=\"";
constexpr std::string_view kPieceClose = "</script>\n";

template <class T>
void appendPiece(std::string& out, std::string_view series, const std::vector<T>& numbers) {
  static_assert(std::endian::native == std::endian::little,
                "the page's numbers are little-endian: swap bytes on this machine");
  if (numbers.empty()) return;
  out += kPieceOpen;
  out += series;
  out += "\">";
  output::appendBase64(out, numbers.data(), numbers.size() * sizeof(T));
  out += kPieceClose;
}

// Frames per piece: the page's series are cut at every kPieceFrames-th kept frame.
constexpr std::size_t kPieceFrames = 64;
// The most a piece's element adds to its base64 (tags, the longest name, padding).
constexpr std::size_t kPieceBytes = kPieceOpen.size() + 16 + 2 + kPieceClose.size() + 4;

}  // namespace

// A named namespace, not the anonymous one: ReplayPageStream::Pieces (replay.h)
// holds one, and a unity build would see that as a subobject of internal linkage.
namespace replay_series {

// The series as pieces, in the page's order (docs/viewer.md, "The page's data"):
// piece k holds kept frames k·K to (k+1)·K - 1 (K = kPieceFrames) and the
// kept rows of each table (energy, joints, contacts) from where piece k - 1
// ended up to the last whose time is at most that of piece k's last frame;
// the last piece, all that is left. A run writes the pieces as its rows come
// (ReplayPageStream), the whole page the same pieces at once: the same bytes.
class SeriesPieces {
 public:
  // Appends the pieces whose rows are all there: those followed by a kept frame
  // (the tables' rows come in time order), and with `last` the rest.
  void append(std::string& out, const ReplayRows& rows, std::size_t particles, const Kept& frames,
              const Kept& energy, const Kept& joints, const Kept& contacts, bool last) {
    while (!done_) {
      const std::size_t begin = piece_ * kPieceFrames;
      const std::size_t end = begin + kPieceFrames;
      const bool final = !(frames.count > end);
      if (final && !last) return;
      const std::size_t frameEnd = final ? frames.count : end;
      const std::size_t width = 3 * particles;
      appendPiece(out, "frames.t",
                  keptValues<double>(rows.frameTime.data(), 1, 0, 1, frames, begin, frameEnd));
      appendPiece(
          out, "frames.position",
          keptValues<float>(rows.framePosition.data(), width, 0, width, frames, begin, frameEnd));
      const double cut = final ? 0.0 : rows.frameTime[frames[end - 1]];
      appendRows(out, "energy", rows.energy, energy, energy_, cut, final);
      appendRows(out, "joints", rows.joints, joints, joints_, cut, final);
      appendRows(out, "contacts", rows.contacts, contacts, contacts_, cut, final);
      cut_ = cut;
      ++piece_;
      done_ = final;
    }
  }
  // Whether a table's row came after a piece that should have held it (not in
  // time order): these pieces are not the whole page's.
  bool outOfOrder() const { return outOfOrder_; }

 private:
  void appendRows(std::string& out, std::string_view name, const ReplaySeries& series,
                  const Kept& kept, std::size_t& next, double cut, bool final) {
    const std::size_t width = series.columns.size();
    if (width == 0) return;
    const auto time = [&](std::size_t k) { return series.values[kept[k] * width]; };
    const std::size_t from = next;
    if (piece_ > 0 && from < kept.count && time(from) <= cut_) outOfOrder_ = true;
    if (final) {
      next = kept.count;
    } else {
      while (next < kept.count && time(next) <= cut) ++next;
    }
    const std::string prefix(name);
    appendPiece(out, prefix + ".t",
                keptValues<double>(series.values.data(), width, 0, 1, kept, from, next));
    appendPiece(out, prefix + ".values",
                keptValues<float>(series.values.data(), width, 1, width - 1, kept, from, next));
  }

  std::size_t piece_ = 0;                               // the next piece
  std::size_t energy_ = 0, joints_ = 0, contacts_ = 0;  // each table's next kept row
  double cut_ = 0.0;                                    // the time that ended the last piece
  bool done_ = false, outOfOrder_ = false;
};

}  // namespace replay_series

namespace {

using replay_series::SeriesPieces;

// How many rows keptIndices keeps.
std::size_t keptCount(std::size_t count, std::size_t stride) {
  if (count == 0) return 0;
  return (count - 1) / stride + 1 + ((count - 1) % stride != 0 ? 1 : 0);
}

// The page's bytes for `count` rows of `width` numbers of `size` bytes each.
std::size_t encodedBytes(std::size_t count, std::size_t width, std::size_t size) {
  return output::base64Size(count * width * size);
}

// A table's kept rows: their times (the first column) as doubles, the rest as floats.
std::size_t seriesBytes(const ReplaySeries& series, std::size_t stride) {
  const std::size_t kept = keptCount(series.rows(), stride);
  const std::size_t width = series.columns.size();
  return width == 0
             ? 0
             : encodedBytes(kept, 1, sizeof(double)) + encodedBytes(kept, width - 1, sizeof(float));
}

// The frames' bytes, with every piece's tags (eight series a piece at most).
std::size_t frameBytes(const ReplayRows& rows, std::size_t particles, std::size_t stride) {
  const std::size_t kept = keptCount(rows.frameTime.size(), stride);
  const std::size_t pieces = kept / kPieceFrames + 1;
  return encodedBytes(kept, 1, sizeof(double)) + encodedBytes(kept, 3 * particles, sizeof(float)) +
         8 * pieces * kPieceBytes;
}

// The smallest stride whose kept rows (`bytes(stride)`) fit in `budget` bytes
// (`count` if none does).
template <class Bytes>
std::size_t strideToFit(std::size_t count, const Bytes& bytes, std::size_t budget) {
  const std::size_t total = bytes(1);
  if (total <= budget || count <= 1) return 1;
  std::size_t stride = std::max<std::size_t>(1, total / std::max<std::size_t>(budget, 1));
  while (stride < count && bytes(stride) > budget)
    stride = std::max(stride + 1, stride + stride / 8);
  return std::min(stride, count);
}

// "name":{"columns":[..],"sourceRows":R,
void appendTableStart(std::string& out, const char* name, const ReplaySeries& series) {
  fmt::format_to(std::back_inserter(out), ",\"{}\":{{\"columns\":[", name);
  for (std::size_t c = 0; c < series.columns.size(); ++c) {
    if (c > 0) out += ',';
    out += jsonString(series.columns[c]);
  }
  fmt::format_to(std::back_inserter(out), "],\"sourceRows\":{}", series.rows());
}

// The first row of each time of the contacts (a row's t is its first number).
std::vector<std::size_t> contactTimeStarts(const ReplaySeries& series) {
  const std::size_t width = series.columns.size();
  std::vector<std::size_t> groupStart;
  for (std::size_t r = 0; r < series.rows(); ++r) {
    if (r == 0 || series.values[r * width] != series.values[(r - 1) * width])
      groupStart.push_back(r);
  }
  return groupStart;
}

// Contacts are decimated by time groups, so a kept time keeps all its
// contacts: the kept rows, and the number of times.
std::vector<std::size_t> keptContacts(const ReplaySeries& series, std::size_t stride,
                                      std::size_t& times) {
  const std::size_t rows = series.rows();
  const std::vector<std::size_t> groupStart = contactTimeStarts(series);
  times = groupStart.size();
  std::vector<std::size_t> kept;
  for (std::size_t g : keptIndices(groupStart.size(), stride)) {
    const std::size_t end = g + 1 < groupStart.size() ? groupStart[g + 1] : rows;
    for (std::size_t r = groupStart[g]; r < end; ++r) kept.push_back(r);
  }
  return kept;
}

// What the page keeps of a run: a stride for the frames and for each table.
struct PageStrides {
  std::size_t frames = 1, energy = 1, joints = 1, contacts = 1;
  bool all() const { return frames == 1 && energy == 1 && joints == 1 && contacts == 1; }
};

// The page of a run folder as it is made: its model part and strides.
struct PagePlan {
  std::filesystem::path path;
  std::string model;  // the data object's model part (and world)
  std::size_t particles = 0;
  PageStrides strides;
  double cap = 0.0;
};

std::size_t pageFixedBytes(const std::string& model) {
  return piecesSize(replay_assets::kPageHead) + piecesSize(replay_assets::kPageMiddle) +
         piecesSize(replay_assets::kPageTail) + model.size() + kSlackBytes;
}

// The plan of the page of the run in `runDir` (`run`: model.json's fields) for
// its series `rows`: the strides that keep it under the cap.
bool planPage(const std::string& runDir, const ReplayOptions& options, const RunFolder& run,
              const ReplayRows& rows, PagePlan& plan, std::string& error) {
  plan.path =
      options.outputPath.empty() ? fs::path(runDir) / "replay.html" : fs::path(options.outputPath);
  std::string world;
  if (!readWorldView(fs::path(runDir), world, error)) return false;
  plan.model = modelJson(run);
  if (!world.empty()) plan.model += ",\"world\":" + world;
  // The robots' meshes, once.
  plan.model += output::meshFilesJson(world, options.sizeCapBytes, output::kMeshBudgetBytes,
                                      output::kMeshTriangleBudget, options.warnings);
  if (options.live) plan.model += ",\"live\":{\"socket\":\"/ws\"}";
  plan.particles = static_cast<std::size_t>(run.particleCount);
  if (rows.framePosition.size() != rows.frameTime.size() * 3 * plan.particles) {
    error = fmt::format("{}: {} positions for {} frames of {} particles", runDir,
                        rows.framePosition.size(), rows.frameTime.size(), plan.particles);
    return false;
  }
  // Budget: the cap less the page itself and the model; plot rows may take up to
  // a quarter of what is left, frames the rest.
  const std::size_t fixedBytes = pageFixedBytes(plan.model);
  plan.cap = options.sizeCapBytes;
  if (!(plan.cap > static_cast<double>(fixedBytes))) {
    error = fmt::format("size cap {} bytes is smaller than the page without frames ({} bytes)",
                        plan.cap, fixedBytes);
    return false;
  }
  const auto available = static_cast<std::size_t>(plan.cap) - fixedBytes;
  const std::size_t allSeriesBytes =
      seriesBytes(rows.energy, 1) + seriesBytes(rows.joints, 1) + seriesBytes(rows.contacts, 1);
  const auto framesAt = [&](std::size_t stride) {
    return frameBytes(rows, plan.particles, stride);
  };
  double seriesShare = 1.0;  // fraction of each plot table kept
  PageStrides& strides = plan.strides;
  if (framesAt(1) + allSeriesBytes > available) {
    const std::size_t seriesBudget = std::min(allSeriesBytes, available / 4);
    seriesShare = allSeriesBytes > 0
                      ? static_cast<double>(seriesBudget) / static_cast<double>(allSeriesBytes)
                      : 1.0;
    strides.frames = strideToFit(rows.frameTime.size(), framesAt, available - seriesBudget);
  }
  auto seriesStride = [&](const ReplaySeries& series) {
    if (seriesShare >= 1.0) return std::size_t{1};
    const auto bytesAt = [&](std::size_t stride) { return seriesBytes(series, stride); };
    return strideToFit(series.rows(), bytesAt,
                       static_cast<std::size_t>(seriesShare * static_cast<double>(bytesAt(1))));
  };
  strides.energy = seriesStride(rows.energy);
  strides.joints = seriesStride(rows.joints);
  strides.contacts = seriesStride(rows.contacts);
  return true;
}

// The data object (in the order viewer/replay.js reads it) of the kept rows.
std::string dataObject(const PagePlan& plan, const RunFolder& run, const ReplayRows& rows,
                       std::size_t keptFrames, std::size_t keptEnergy, std::size_t keptJoints,
                       std::size_t keptContacts, std::size_t contactTimes) {
  const PageStrides& s = plan.strides;
  std::string data = "{" + plan.model;
  fmt::format_to(std::back_inserter(data), ",\"threeVersion\":\"{}\",\"sizeCapBytes\":{}",
                 replay_assets::kThreeVersion, plan.cap);
  fmt::format_to(std::back_inserter(data),
                 ",\"frames\":{{\"sourceCount\":{},\"stride\":{},\"count\":{}}}",
                 rows.frameTime.size(), s.frames, keptFrames);
  appendTableStart(data, "energy", rows.energy);
  fmt::format_to(std::back_inserter(data), ",\"stride\":{},\"count\":{}}}", s.energy, keptEnergy);
  if (rows.hasJoints) {
    appendTableStart(data, "joints", rows.joints);
    fmt::format_to(std::back_inserter(data), ",\"stride\":{},\"count\":{}}}", s.joints, keptJoints);
    data += ",\"jointKinds\":[";
    for (std::size_t j = 0; j < run.jointKinds.size(); ++j) {
      if (j > 0) data += ',';
      data += jsonString(run.jointKinds[j]);
    }
    data += ']';
  }
  if (rows.hasContacts) {
    appendTableStart(data, "contacts", rows.contacts);
    fmt::format_to(std::back_inserter(data), ",\"sourceTimes\":{},\"stride\":{},\"count\":{}}}",
                   contactTimes, s.contacts, keptContacts);
  }
  data += '}';
  return data;
}

// The page's bytes after its series: the data element's start, the data, the rest.
std::size_t pageEndBytes(const std::string& data) {
  return piecesSize(replay_assets::kPageMiddle) + data.size() +
         piecesSize(replay_assets::kPageTail);
}

// Writes the page after its series (pageEndBytes).
void writePageEnd(std::ostream& out, const std::string& data) {
  writePieces(out, replay_assets::kPageMiddle);
  out << data;
  writePieces(out, replay_assets::kPageTail);
}

std::string overCap(const PagePlan& plan, std::size_t pageBytes, std::size_t keptFrames,
                    std::size_t frames) {
  return fmt::format(
      "{}: the page would be {} bytes, over the cap of {} bytes even with {} of {} frames; "
      "raise the cap",
      plan.path.string(), pageBytes, plan.cap, keptFrames, frames);
}

// Lists a page about to be written into a robophi run folder in its marker
// (before it is there: a kill in between leaves a folder wholly robophi's).
void listPage(const PagePlan& plan) {
  if (plan.path.has_parent_path())
    output::addToResultsMarker(plan.path.parent_path(), plan.path.filename().string());
}

// Takes a page that could not be written off the marker again.
void unlistPage(const PagePlan& plan) {
  try {
    if (plan.path.has_parent_path())
      output::removeFromResultsMarker(plan.path.parent_path(), plan.path.filename().string());
  } catch (const std::exception&) {  // (the error already says what failed)
  }
}

// The whole page of the plan, written at once (whole or not at all).
bool writeWholePage(const PagePlan& plan, const RunFolder& run, const ReplayRows& rows,
                    std::string& error) {
  const std::vector<std::size_t> frameRows =
      keptIndices(rows.frameTime.size(), plan.strides.frames);
  const std::vector<std::size_t> energyRows = keptIndices(rows.energy.rows(), plan.strides.energy);
  const std::vector<std::size_t> jointRows = keptIndices(rows.joints.rows(), plan.strides.joints);
  std::size_t contactTimes = 0;
  const std::vector<std::size_t> contactRows =
      keptContacts(rows.contacts, plan.strides.contacts, contactTimes);
  std::string series;
  series.reserve(frameBytes(rows, plan.particles, plan.strides.frames) +
                 seriesBytes(rows.energy, plan.strides.energy) +
                 seriesBytes(rows.joints, plan.strides.joints) +
                 seriesBytes(rows.contacts, plan.strides.contacts));
  SeriesPieces pieces;
  pieces.append(series, rows, plan.particles, {&frameRows, frameRows.size()},
                {&energyRows, energyRows.size()}, {&jointRows, jointRows.size()},
                {&contactRows, contactRows.size()}, /*last=*/true);
  const std::string data = dataObject(plan, run, rows, frameRows.size(), energyRows.size(),
                                      jointRows.size(), contactRows.size(), contactTimes);
  const std::size_t pageBytes =
      piecesSize(replay_assets::kPageHead) + series.size() + pageEndBytes(data);
  if (static_cast<double>(pageBytes) > plan.cap) {
    error = overCap(plan, pageBytes, frameRows.size(), rows.frameTime.size());
    return false;
  }
  try {
    listPage(plan);
    output::writeFileAtomically(plan.path, [&](std::ostream& out) {
      writePieces(out, replay_assets::kPageHead);
      out << series;
      writePageEnd(out, data);
    });
  } catch (const std::exception& e) {
    error = e.what();
    unlistPage(plan);
    return false;
  }
  return true;
}

}  // namespace

// The page as the run goes: the head, then each piece of the series once its
// rows are all there, into replay.html.partial; finish() adds the rest and
// renames it, when the page keeps every row (else the page is written whole).
struct ReplayPageStream::Pieces {
  fs::path partial;
  std::ofstream out;
  SeriesPieces pieces;
  std::string buffer;
  std::size_t bytes = 0;  // written so far
  double cap = 0.0;       // the page's size cap (bytes)
};

ReplayPageStream::ReplayPageStream(const std::string& runDir, double sizeCapBytes)
    : state_(std::make_unique<Pieces>()) {
  state_->partial = fs::path(runDir) / kReplayPagePartial;
  state_->cap = sizeCapBytes;
}

ReplayPageStream::~ReplayPageStream() { abandon(); }

void ReplayPageStream::abandon() {
  if (!state_) return;
  if (state_->out.is_open() || state_->bytes > 0) {
    state_->out.close();
    std::error_code ec;
    fs::remove(state_->partial, ec);
  }
  state_.reset();
}

bool ReplayPageStream::usable() const { return state_ && !state_->pieces.outOfOrder(); }

void ReplayPageStream::write(const ReplayRows& rows, std::size_t particles, bool last) {
  if (!usable()) return;
  Pieces& s = *state_;
  if (!s.out.is_open()) {
    s.out.open(s.partial, std::ios::binary);
    writePieces(s.out, replay_assets::kPageHead);
    s.bytes += piecesSize(replay_assets::kPageHead);
  }
  s.buffer.clear();
  s.pieces.append(s.buffer, rows, particles, {nullptr, rows.frameTime.size()},
                  {nullptr, rows.energy.rows()}, {nullptr, rows.joints.rows()},
                  {nullptr, rows.contacts.rows()}, last);
  s.out << s.buffer;
  s.bytes += s.buffer.size();
  // Past the cap the page keeps only some rows: it is written whole at the end.
  if (!s.out || static_cast<double>(s.bytes) > s.cap) abandon();
}

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options, std::string& error) {
  RunFolder run;
  if (!output::readRunFolderWithFrames(runDir, /*needEnergy=*/true, run, error)) return false;
  ReplayRows rows;
  rows.frameTime = run.frameTime;
  rows.framePosition.reserve(run.framePosition.size());
  for (double x : run.framePosition) rows.framePosition.push_back(static_cast<float>(x));
  const auto series = [](CsvTable& table) {
    return ReplaySeries{table.columns, std::move(table.values)};
  };
  rows.energy = series(run.energy);
  rows.joints = series(run.joints);
  rows.contacts = series(run.contacts);
  rows.hasJoints = run.hasJoints;
  rows.hasContacts = run.hasContacts;
  PagePlan plan;
  return planPage(runDir, options, run, rows, plan, error) &&
         writeWholePage(plan, run, rows, error);
}

bool writeReplayHtml(const std::string& runDir, const ReplayOptions& options,
                     const ReplayRows& rows, ReplayPageStream* stream, std::string& error) {
  // No frame: the files' own path says what is missing.
  if (rows.frameTime.empty()) {
    if (stream != nullptr) stream->abandon();
    return writeReplayHtml(runDir, options, error);
  }
  RunFolder run;
  PagePlan plan;
  if (!output::readRunModel(runDir, run, error) ||
      !planPage(runDir, options, run, rows, plan, error)) {
    if (stream != nullptr) stream->abandon();
    return false;
  }
  // The pieces written as the run went are this page's when it keeps every row
  // and goes where they went.
  if (stream == nullptr || !stream->usable() || !plan.strides.all() ||
      plan.path != stream->state_->partial.parent_path() / "replay.html") {
    if (stream != nullptr) stream->abandon();
    return writeWholePage(plan, run, rows, error);
  }
  stream->write(rows, plan.particles, /*last=*/true);
  if (!stream->usable()) {  // (rows out of time order, a write failed, or past the cap)
    stream->abandon();
    return writeWholePage(plan, run, rows, error);
  }
  ReplayPageStream::Pieces& s = *stream->state_;
  const std::string data =
      dataObject(plan, run, rows, rows.frameTime.size(), rows.energy.rows(), rows.joints.rows(),
                 rows.contacts.rows(), contactTimeStarts(rows.contacts).size());
  const std::size_t pageBytes = s.bytes + pageEndBytes(data);
  if (static_cast<double>(pageBytes) > plan.cap) {
    error = overCap(plan, pageBytes, rows.frameTime.size(), rows.frameTime.size());
    stream->abandon();
    return false;
  }
  writePageEnd(s.out, data);
  s.out.close();
  std::error_code ec;
  if (!s.out) {
    stream->abandon();
    return writeWholePage(plan, run, rows, error);  // (says what failed)
  }
  try {
    listPage(plan);
  } catch (const std::exception& e) {
    error = e.what();
    stream->abandon();
    return false;
  }
  fs::rename(s.partial, plan.path, ec);
  if (ec) {
    error = fmt::format("{}: cannot write ({})", plan.path.string(), ec.message());
    stream->abandon();
    unlistPage(plan);
    return false;
  }
  stream->state_.reset();  // finished: nothing to remove
  return true;
}

}  // namespace robophi
