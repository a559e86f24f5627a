// The replay page: written from a hand-made run folder, under its size cap (frames
// decimated when needed), with the times of frames and rows exactly as the CSV
// files hold them and what is drawn (positions, plotted values, contact forces)
// in single precision.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "output/base64.h"
#include "output/replay.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

using testing::readText;
using testing::writeText;

// The run data object embedded in the page.
nlohmann::json pageData(const std::string& page) {
  const std::string open = "<script id=\"robophi-data\" type=\"application/json\">";
  const std::size_t start = page.find(open) + open.size();
  return nlohmann::json::parse(page.substr(start, page.find("</script>", start) - start));
}

// A binary series of the page (`name`: "frames.t", "energy.values", ...): its
// pieces' base64 of little-endian numbers of type T, in order, as doubles.
template <class T>
std::vector<double> numbers(const std::string& page, const std::string& name) {
  const std::string open = "data-series=\"" + name + "\">";
  std::vector<double> out;
  for (std::size_t at = page.find(open); at != std::string::npos; at = page.find(open, at)) {
    at += open.size();
    const std::vector<std::uint8_t> bytes =
        output::decodeBase64(page.substr(at, page.find("</script>", at) - at));
    EXPECT_EQ(bytes.size() % sizeof(T), 0u);
    for (std::size_t i = 0; i + sizeof(T) <= bytes.size(); i += sizeof(T)) {
      T value;
      std::memcpy(&value, bytes.data() + i, sizeof(T));
      out.push_back(value);
    }
  }
  return out;
}

// The bytes of the page's pieces of the series whose names start with `prefix`.
std::size_t seriesBytes(const std::string& page, const std::string& prefix) {
  const std::string open = "data-series=\"" + prefix;
  std::size_t bytes = 0;
  for (std::size_t at = page.find(open); at != std::string::npos; at = page.find(open, at + 1))
    bytes += page.find("</script>", at) - at;
  return bytes;
}

// Two particles, `frames` frames at 100 fps with positions that need all 17 digits.
class ReplayHtmlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::makeTempFolder("robophi_replay_test_");
    writeText(dir_ / "model.json", R"({"name": "two </script> balls",
      "particles": {"count": 2, "mass": [1, 1], "radius": [0.1, 0.1], "object": [0, 0],
                    "fixed": [0, 0]},
      "objects": [{"name": "pair", "kind": "rope", "first": 0, "count": 2, "material": 0}],
      "connectors": {"linear": [[0, 1, 1.0]], "torsion": [], "joint": []},
      "joints": [], "gravity": [0, 0, -9.81]})");
    writeText(dir_ / "energy.csv",
              "t,dt,kinetic,potential,dissipated,total\n0,0.001,0,1,0,1\n1,0.001,0.5,0.5,0,1\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void writeFrames(int frames) {
    std::string csv = "t,x0,y0,z0,x1,y1,z1\n";
    for (int k = 0; k < frames; ++k) {
      const double t = k / 100.0;
      fmt::format_to(std::back_inserter(csv), "{},{},0,{},{},0,1\n", t, t / 3.0, 1.0 / (k + 3),
                     1.0 + t / 7.0);
    }
    writeText(dir_ / "particles.csv", csv);
  }

  fs::path dir_;
};

TEST_F(ReplayHtmlTest, KeepsEveryFrameExactlyUnderTheCap) {
  writeFrames(50);
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), {}, error)) << error;
  const std::string page = readText(dir_ / "replay.html");
  // The name's "</script>" must not end the data element early.
  EXPECT_EQ(page.find("two </script>"), std::string::npos);
  const nlohmann::json data = pageData(page);
  EXPECT_EQ(data["name"], "two </script> balls");
  EXPECT_EQ(data["frames"]["stride"], 1);
  EXPECT_EQ(data["frames"]["count"], 50);
  const std::vector<double> t = numbers<double>(page, "frames.t");
  const std::vector<double> position = numbers<float>(page, "frames.position");
  ASSERT_EQ(t.size(), 50u);
  ASSERT_EQ(position.size(), 50u * 2 * 3);
  // Frame 7: the time holds the bits of particles.csv, the positions their nearest floats.
  EXPECT_EQ(t[7], 0.07);
  EXPECT_EQ(position[7 * 6 + 0], static_cast<double>(static_cast<float>(0.07 / 3.0)));
  EXPECT_EQ(position[7 * 6 + 2], static_cast<double>(static_cast<float>(1.0 / 10)));
  EXPECT_EQ(position[7 * 6 + 5], 1.0f);
  // The plotted table: energy.csv's times, and its other numbers as floats, row by row.
  EXPECT_EQ(data["energy"]["columns"].size(), 6u);
  EXPECT_EQ(data["energy"]["count"], 2);
  EXPECT_EQ(numbers<double>(page, "energy.t"), (std::vector<double>{0, 1}));
  const double ms = static_cast<float>(0.001);
  EXPECT_EQ(numbers<float>(page, "energy.values"),
            (std::vector<double>{ms, 0, 1, 0, 1, ms, 0.5, 0.5, 0, 1}));
  EXPECT_FALSE(data.contains("contacts"));
}

TEST_F(ReplayHtmlTest, DecimatesFramesToStayUnderTheCap) {
  writeFrames(20000);
  ReplayOptions options;
  options.outputPath = (dir_ / "small.html").string();
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), options, error)) << error;
  const auto fullPage = static_cast<double>(fs::file_size(options.outputPath));
  const auto framesBytes =
      static_cast<double>(seriesBytes(readText(options.outputPath), "frames."));
  // A cap that leaves room for about a quarter of the frames.
  options.sizeCapBytes = fullPage - 0.75 * framesBytes;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), options, error)) << error;
  EXPECT_LE(static_cast<double>(fs::file_size(options.outputPath)), options.sizeCapBytes);
  const std::string page = readText(options.outputPath);
  const nlohmann::json data = pageData(page);
  const int stride = data["frames"]["stride"].get<int>();
  EXPECT_GE(stride, 4);
  EXPECT_LE(stride, 5);
  EXPECT_EQ(data["frames"]["sourceCount"], 20000);
  const std::vector<double> t = numbers<double>(page, "frames.t");
  ASSERT_EQ(t.size(), data["frames"]["count"].get<std::size_t>());
  EXPECT_EQ(numbers<float>(page, "frames.position").size(), t.size() * 6);
  EXPECT_EQ(t.front(), 0.0);
  EXPECT_EQ(t[1], stride / 100.0);
  EXPECT_EQ(t.back(), 19999 / 100.0);  // the last frame is always kept
}

TEST_F(ReplayHtmlTest, RefusesACapSmallerThanThePage) {
  writeFrames(5);
  ReplayOptions options;
  options.sizeCapBytes = 1000;
  std::string error;
  EXPECT_FALSE(writeReplayHtml(dir_.string(), options, error));
  EXPECT_NE(error.find("size cap"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir_ / "replay.html"));
}

TEST_F(ReplayHtmlTest, NamesAMissingEnergyFile) {
  writeFrames(5);
  fs::remove(dir_ / "energy.csv");
  std::string error;
  EXPECT_FALSE(writeReplayHtml(dir_.string(), {}, error));
  EXPECT_NE(error.find("energy.csv"), std::string::npos) << error;
}

TEST_F(ReplayHtmlTest, NamesABadContactsColumn) {
  writeFrames(5);
  writeText(dir_ / "contacts.csv", "t,a,b,fx,fy\n0,0,1,0,0\n");
  std::string error;
  EXPECT_FALSE(writeReplayHtml(dir_.string(), {}, error));
  EXPECT_NE(error.find("contacts.csv:1: missing column 'fz'"), std::string::npos) << error;
}

TEST_F(ReplayHtmlTest, EmbedsTheWorldAndTheContactColumns) {
  writeFrames(5);
  // world.json (output/world_view.h) goes into the page as "world", safely inside <script>.
  writeText(dir_ / "world.json", R"({"environment": {"planes": [{"point": [0, 0, 0],
    "normal": [0, 0, 1]}], "heightfields": [], "boxes": [], "spheres": []},
    "goals": [{"name": "a </script> goal"}], "paths": [], "attractors": [0]})");
  writeText(dir_ / "contacts.csv", "t,a,b,fx,fy,fz,tx,ty,tz,sliding\n0.01,0,2,0,0,1,0.5,0,0,1\n");
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), {}, error)) << error;
  const std::string page = readText(dir_ / "replay.html");
  EXPECT_EQ(page.find("a </script>"), std::string::npos);
  const nlohmann::json data = pageData(page);
  ASSERT_TRUE(data.contains("world"));
  EXPECT_EQ(data["world"]["environment"]["planes"].size(), 1u);
  EXPECT_EQ(data["world"]["goals"][0]["name"], "a </script> goal");
  EXPECT_EQ(data["world"]["attractors"][0], 0);
  EXPECT_EQ(data["contacts"]["columns"],
            nlohmann::json::parse(R"(["t","a","b","fx","fy","fz","tx","ty","tz","sliding"])"));
  EXPECT_EQ(data["contacts"]["count"], 1);
  EXPECT_EQ(numbers<double>(page, "contacts.t"), (std::vector<double>{0.01}));
  EXPECT_EQ(numbers<float>(page, "contacts.values"),
            (std::vector<double>{0, 2, 0, 0, 1, 0.5, 0, 0, 1}));
}

TEST_F(ReplayHtmlTest, WorksWithoutAWorldFile) {
  writeFrames(5);
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), {}, error)) << error;
  EXPECT_FALSE(pageData(readText(dir_ / "replay.html")).contains("world"));
}

TEST_F(ReplayHtmlTest, NamesAMalformedWorldFile) {
  writeFrames(5);
  writeText(dir_ / "world.json", "{\"environment\": [1, 2");
  std::string error;
  EXPECT_FALSE(writeReplayHtml(dir_.string(), {}, error));
  EXPECT_NE(error.find("world.json"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir_ / "replay.html"));
}

// energy.csv with `rows` rows at 200 per second (two a frame), its kinetic energy
// the row's index.
void writeEnergy(const fs::path& dir, int rows) {
  std::string csv = "t,dt,kinetic,potential,dissipated,total\n";
  for (int k = 0; k < rows; ++k)
    fmt::format_to(std::back_inserter(csv), "{},0.001,{},1,0,1\n", k / 200.0, k);
  writeText(dir / "energy.csv", csv);
}

// How many pieces the page has of series `name`, and the first one's bytes.
std::size_t pieceCount(const std::string& page, const std::string& name, std::size_t* firstBytes) {
  const std::string open = "data-series=\"" + name + "\">";
  std::size_t count = 0;
  for (std::size_t at = page.find(open); at != std::string::npos; at = page.find(open, at + 1)) {
    if (count++ == 0 && firstBytes != nullptr) {
      const std::size_t begin = at + open.size();
      *firstBytes =
          output::decodeBase64(page.substr(begin, page.find("</script>", begin) - begin)).size();
    }
  }
  return count;
}

TEST_F(ReplayHtmlTest, CutsItsSeriesIntoPiecesAtEvery64thFrame) {
  writeFrames(200);        // pieces of 64, 64, 64 and 8 frames
  writeEnergy(dir_, 401);  // the last row after the last frame
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), {}, error)) << error;
  const std::string page = readText(dir_ / "replay.html");
  std::size_t first = 0;
  EXPECT_EQ(pieceCount(page, "frames.t", &first), 4u);
  EXPECT_EQ(first, 64u * sizeof(double));
  EXPECT_EQ(pieceCount(page, "frames.position", &first), 4u);
  EXPECT_EQ(first, 64u * 6 * sizeof(float));
  // The first energy piece: the rows up to frame 63's time (0.63 s), 127 of them.
  EXPECT_EQ(pieceCount(page, "energy.t", &first), 4u);
  EXPECT_EQ(first, 127u * sizeof(double));
  // Read back whole, in order.
  const std::vector<double> t = numbers<double>(page, "energy.t");
  const std::vector<double> values = numbers<float>(page, "energy.values");
  ASSERT_EQ(t.size(), 401u);
  ASSERT_EQ(values.size(), 401u * 5);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(t[k], static_cast<double>(k) / 200.0);
    EXPECT_EQ(values[5 * k + 1], static_cast<double>(k));
  }
  EXPECT_EQ(numbers<double>(page, "frames.t").size(), 200u);
  // The series come before the data object, and it says what they hold.
  const nlohmann::json data = pageData(page);
  EXPECT_EQ(data["frames"]["count"], 200);
  EXPECT_EQ(data["energy"]["count"], 401);
  EXPECT_FALSE(data["frames"].contains("t"));
}

// The rows of the fixture's `frames` frames and 2 `frames` + 1 energy rows (as
// writeFrames and writeEnergy write them) as a run gathers them.
struct FixtureRows {
  ReplayRows all;
  explicit FixtureRows(int frames = 200) {
    for (int k = 0; k < frames; ++k) {
      const double t = k / 100.0;
      all.frameTime.push_back(t);
      for (const double x : {t / 3.0, 0.0, 1.0 / (k + 3), 1.0 + t / 7.0, 0.0, 1.0})
        all.framePosition.push_back(static_cast<float>(x));
    }
    all.energy.columns = {"t", "dt", "kinetic", "potential", "dissipated", "total"};
    for (int k = 0; k <= 2 * frames; ++k)
      all.energy.values.insert(all.energy.values.end(), {k / 200.0, 0.001, 1.0 * k, 1, 0, 1});
  }
  // Hands the rows to `stream` as a run would: frames and energy rows in time
  // order (or, with `energyLate`, the energy rows after every frame), written
  // every `batch` rows.
  void feed(ReplayPageStream& stream, ReplayRows& rows, std::size_t batch, bool energyLate) const {
    rows = ReplayRows{};
    rows.energy.columns = all.energy.columns;
    std::size_t f = 0, e = 0, taken = 0;
    while (f < all.frameTime.size() || e < all.energy.rows()) {
      const bool frameNext =
          e == all.energy.rows() ||
          (f < all.frameTime.size() && (energyLate || all.frameTime[f] < all.energy.values[6 * e]));
      if (frameNext) {
        rows.frameTime.push_back(all.frameTime[f]);
        rows.framePosition.insert(rows.framePosition.end(), all.framePosition.begin() + 6 * f,
                                  all.framePosition.begin() + 6 * (f + 1));
        ++f;
      } else {
        rows.energy.values.insert(rows.energy.values.end(), all.energy.values.begin() + 6 * e,
                                  all.energy.values.begin() + 6 * (e + 1));
        ++e;
      }
      if (++taken % batch == 0) stream.write(rows, 2);
    }
  }
};

TEST_F(ReplayHtmlTest, ThePageWrittenAsTheRowsComeIsThePageFromTheFiles) {
  writeFrames(200);
  writeEnergy(dir_, 401);
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), {}, error)) << error;
  const std::string fromFiles = readText(dir_ / "replay.html");
  const FixtureRows fixture;
  // In batches of every size, the rows in time order; and the energy rows late
  // (the pieces written so far are not the page's: it is written whole).
  for (const bool late : {false, true}) {
    for (const std::size_t batch : {1, 7, 64, 65, 1000}) {
      fs::remove(dir_ / "replay.html");
      const ReplayOptions options;
      ReplayPageStream stream(dir_.string(), options.sizeCapBytes);
      ReplayRows rows;
      fixture.feed(stream, rows, batch, late);
      ASSERT_TRUE(writeReplayHtml(dir_.string(), options, rows, &stream, error)) << error;
      EXPECT_TRUE(readText(dir_ / "replay.html") == fromFiles)
          << "batch " << batch << ", late " << late;
      EXPECT_FALSE(fs::exists(dir_ / "replay.html.partial"));
    }
  }
}

// A page past its cap as it is written gives up (it keeps only some rows): the
// page is written whole at the end, the one made from the files.
TEST_F(ReplayHtmlTest, APagePastItsCapAsItIsWrittenIsWrittenWholeAtTheEnd) {
  writeFrames(4000);
  writeEnergy(dir_, 8001);
  ReplayOptions options;
  std::string error;
  ASSERT_TRUE(writeReplayHtml(dir_.string(), options, error)) << error;
  // A cap 150 kB under the whole page (its series 0.5 MB): some rows are dropped.
  options.sizeCapBytes = static_cast<double>(fs::file_size(dir_ / "replay.html") - 150000);
  ASSERT_TRUE(writeReplayHtml(dir_.string(), options, error)) << error;
  const std::string fromFiles = readText(dir_ / "replay.html");
  const nlohmann::json data = pageData(fromFiles);
  EXPECT_GT(data["frames"]["stride"].get<int>() + data["energy"]["stride"].get<int>(), 2);
  fs::remove(dir_ / "replay.html");
  const FixtureRows fixture(4000);
  ReplayPageStream stream(dir_.string(), options.sizeCapBytes);
  ReplayRows rows;
  fixture.feed(stream, rows, 100, false);
  EXPECT_FALSE(stream.usable());  // (past the cap before the last frames)
  EXPECT_FALSE(fs::exists(dir_ / "replay.html.partial"));
  ASSERT_TRUE(writeReplayHtml(dir_.string(), options, rows, &stream, error)) << error;
  EXPECT_TRUE(readText(dir_ / "replay.html") == fromFiles);
}

TEST_F(ReplayHtmlTest, APageNotEndedLeavesNothing) {
  const FixtureRows fixture;
  {
    ReplayPageStream stream(dir_.string(), ReplayOptions{}.sizeCapBytes);
    ReplayRows rows;
    fixture.feed(stream, rows, 10, false);
    EXPECT_TRUE(fs::exists(dir_ / "replay.html.partial"));
  }
  EXPECT_FALSE(fs::exists(dir_ / "replay.html.partial"));
  EXPECT_FALSE(fs::exists(dir_ / "replay.html"));
}

}  // namespace
}  // namespace robophi
