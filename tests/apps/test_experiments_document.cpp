// docs/experiments.md is what `robophi study experiments --out docs` writes: a
// fresh study, run here as a user runs it (from the checkout's root, so that the
// scene paths read scenes/...), must give the document's every line but the
// nondeterministic ones: the date and version it was generated with, and the
// wall-time and real-time-factor columns. Outcomes, simulated times, step counts,
// energy drifts and events are deterministic (the same build gives the same bits)
// and must match to the last printed digit. A stale document fails here with the
// command that regenerates it. The whole study: about 8 s of wall time on an idle
// 2-core machine, so under the ctest label slow (out of the sanitizer pass).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <cctype>
#include <sstream>
#include <string>
#include <vector>

#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using testing::readText;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The line as far as a fresh run must reproduce it: the generation date and the
// version masked, and in a table row of the experiments the cells "wall s" and
// "× real time" (the 5th and 6th of 7) masked.
// (Plain scanning, no std::regex: GCC 12's sanitizer build warns inside <regex>.)
std::string deterministicPart(std::string line) {
  // "on YYYY-MM-DD," → "on DATE,".
  const auto digits = [&](std::size_t at, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k)
      if (at + k >= line.size() || !std::isdigit(static_cast<unsigned char>(line[at + k]))) return false;
    return true;
  };
  for (std::size_t at = line.find("on "); at != std::string::npos; at = line.find("on ", at + 1)) {
    const std::size_t d = at + 3;
    if (digits(d, 4) && d + 10 < line.size() && line[d + 4] == '-' && digits(d + 5, 2) &&
        line[d + 7] == '-' && digits(d + 8, 2) && line[d + 10] == ',') {
      line.replace(at, 14, "on DATE,");
      break;
    }
  }
  // "robophi VERSION;" at the start.
  if (line.rfind("robophi ", 0) == 0) {
    const std::size_t semicolon = line.find(';');
    if (semicolon != std::string::npos && semicolon > 8) line.replace(0, semicolon + 1, "robophi VERSION;");
  }
  if (line.rfind("| ", 0) != 0 || line.rfind("|---", 0) == 0) return line;
  // Split on the cell separators " | " (an escaped \| inside a cell is not one).
  std::vector<std::string> cells;
  std::size_t start = 0;
  for (std::size_t at = line.find(" | "); at != std::string::npos; at = line.find(" | ", at + 3)) {
    if (at > 0 && line[at - 1] == '\\') continue;
    cells.push_back(line.substr(start, at - start));
    start = at + 3;
  }
  cells.push_back(line.substr(start));
  if (cells.size() != 7 || cells[0] == "| experiment") return line;
  cells[4] = "WALL";
  cells[5] = "FACTOR";
  std::string masked;
  for (const std::string& cell : cells) masked += (masked.empty() ? "" : " | ") + cell;
  return masked;
}

class Experiments : public ::testing::TestWithParam<const char*> {};

TEST_P(Experiments, DocumentEqualsAFreshStudy) {
  const fs::path root = testing::makeTempFolder("robophi_experiments_doc_");
  const std::string command = std::string("cd " ROBOPHI_SOURCE_DIR " && ") + ROBOPHI_BINARY +
                              " study experiments --out " + root.string() + " > " +
                              (root / "log.txt").string() + " 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << readText(root / "log.txt");
  ASSERT_EQ(WEXITSTATUS(status), 0) << readText(root / "log.txt");
  const std::vector<std::string> fresh = lines(readText(root / "experiments.md"));
  const std::vector<std::string> document = lines(readText(GetParam()));
  ASSERT_FALSE(fresh.empty()) << readText(root / "log.txt");
  const char* regenerate =
      "docs/experiments.md is stale; regenerate it from the checkout's root with\n"
      "  build/robophi study experiments --out docs --record bench/results";
  EXPECT_EQ(document.size(), fresh.size()) << regenerate;
  for (std::size_t i = 0; i < std::min(document.size(), fresh.size()); ++i)
    EXPECT_EQ(deterministicPart(document[i]), deterministicPart(fresh[i]))
        << "line " << i + 1 << " of " << GetParam() << "\n"
        << regenerate;
  fs::remove_all(root);
}

INSTANTIATE_TEST_SUITE_P(Slow, Experiments,
                         ::testing::Values(ROBOPHI_SOURCE_DIR "/docs/experiments.md"));

TEST(ExperimentsDocument, MasksOnlyTheWallTimesDateAndVersion) {
  EXPECT_EQ(deterministicPart("| 5 ball | `scenes/b.json` | e = 0.9 \\| x | 1.5 | 0.000298 | 5.04e+03 "
                              "| 590 (64) |"),
            "| 5 ball | `scenes/b.json` | e = 0.9 \\| x | 1.5 | WALL | FACTOR | 590 (64) |");
  EXPECT_EQ(deterministicPart("Generated by `robophi study experiments` (x) on 2026-12-04,"),
            "Generated by `robophi study experiments` (x) on DATE,");
  EXPECT_EQ(deterministicPart("robophi 0.1.0; the same data"), "robophi VERSION; the same data");
  EXPECT_EQ(deterministicPart("- status ok, energy drift 3.55e-07"),
            "- status ok, energy drift 3.55e-07");
}

}  // namespace
}  // namespace robophi
