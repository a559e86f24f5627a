// The broken-scene corpus (tests/scene/broken/, README.md there): every scene
// file of the folder, and every command line of its table, is refused with the
// exit code, the place and the message its row of expected.txt states, by the
// loader, by `robophi validate` and by `robophi run`, and nothing is written to
// the run's output folder.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "robophi/scene/scene.h"
#include "scene/scene_test_util.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(ROBOPHI_SOURCE_DIR) / "tests/scene/broken";

// One row of expected.txt: `case | exit | place | message`.
struct BrokenCase {
  std::string label;
  /// "name.json" (a scene of the folder) or "run ARGS" (a command line).
  std::string target;
  int exitCode = 0;
  /// Scenes: what follows the file's path in the message (":line:column", or
  /// "" when the file has no place); command lines: a text the message quotes.
  std::string place;
  std::string fragment;
  bool isScene() const { return target.find(' ') == std::string::npos; }
};

// For gtest's messages: the row, not its bytes.
void PrintTo(const BrokenCase& c, std::ostream* out) {
  *out << c.target << " | " << c.exitCode << " | " << c.place << " | " << c.fragment;
}

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return {};
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

std::vector<BrokenCase> readCases() {
  std::vector<BrokenCase> cases;
  std::ifstream in(kCorpus / "expected.txt");
  std::string line;
  while (std::getline(in, line)) {
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    std::vector<std::string> fields;
    std::size_t start = 0;
    // Three separators; the message (last) may hold '|' itself.
    for (int k = 0; k < 3; ++k) {
      const auto bar = line.find('|', start);
      if (bar == std::string::npos) break;
      fields.push_back(trim(line.substr(start, bar - start)));
      start = bar + 1;
    }
    fields.push_back(trim(line.substr(start)));
    if (fields.size() != 4) {
      ADD_FAILURE() << "expected.txt: not 'case | exit | place | message': " << line;
      continue;
    }
    BrokenCase c;
    c.target = fields[0];
    c.exitCode = std::atoi(fields[1].c_str());
    c.place = fields[2];
    c.fragment = fields[3];
    c.label = c.isScene() ? c.target.substr(0, c.target.size() - 5) : "cli " + c.target;
    cases.push_back(c);
  }
  return cases;
}

struct BrokenOutcome {
  int exitCode = -1;
  std::string errors;
};

// `robophi <args>`: its exit code and what it wrote to stderr.
BrokenOutcome robophi(const std::string& args, const fs::path& scratch) {
  const fs::path errors = scratch / "stderr.txt";
  const std::string command =
      std::string(ROBOPHI_BINARY) + " " + args + " > /dev/null 2> " + errors.string();
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(errors)};
}

class BrokenScene : public ::testing::TestWithParam<BrokenCase> {
 protected:
  void SetUp() override { scratch_ = testing::makeTempFolder("robophi_broken_"); }
  void TearDown() override { fs::remove_all(scratch_); }
  fs::path scratch_;
};

TEST_P(BrokenScene, IsRefusedWithItsPlaceAndMessageAndWritesNothing) {
  const BrokenCase& c = GetParam();
  const fs::path out = scratch_ / "out";
  if (!c.isScene()) {
    // A command line over a valid scene: {scenes} is the shipped scenes' folder.
    std::string args = c.target;
    const std::string token = "{scenes}";
    for (auto at = args.find(token); at != std::string::npos; at = args.find(token))
      args.replace(at, token.size(), ROBOPHI_SOURCE_DIR "/scenes");
    const bool run = args.starts_with("run ");
    const BrokenOutcome o = robophi(args + (run ? " --quiet --out " + out.string() : ""), scratch_);
    EXPECT_EQ(o.exitCode, c.exitCode) << o.errors;
    EXPECT_NE(o.errors.find(c.place), std::string::npos) << o.errors;
    EXPECT_NE(o.errors.find(c.fragment), std::string::npos) << o.errors;
    EXPECT_FALSE(fs::exists(out)) << "robophi " << args << " wrote " << out;
    return;
  }
  const fs::path scene = kCorpus / c.target;
  ASSERT_TRUE(fs::exists(scene)) << scene;
  const std::string where = scene.string() + c.place;

  // The loader: no scene, and an error with the place and the message.
  const SceneLoadResult result = loadSceneFile(scene.string());
  EXPECT_FALSE(result.ok());
  bool found = false;
  for (const Diagnostic& d : result.errors) {
    const std::string text = d.format();
    found = found || (text.find(c.fragment) != std::string::npos &&
                      text.starts_with(where + (c.place.empty() ? "" : ":")));
  }
  EXPECT_TRUE(found) << "no error at " << where << " saying '" << c.fragment << "':\n"
                     << test::allErrors(result);

  // validate and run: the exit code and the same message on stderr; run writes nothing.
  for (const std::string command : {"validate", "run"}) {
    SCOPED_TRACE(command);
    const std::string extra = command == "run" ? " --quiet --out " + out.string() : "";
    const BrokenOutcome o = robophi(command + " " + scene.string() + extra, scratch_);
    EXPECT_EQ(o.exitCode, c.exitCode) << o.errors;
    EXPECT_NE(o.errors.find(where), std::string::npos) << o.errors;
    EXPECT_NE(o.errors.find(c.fragment), std::string::npos) << o.errors;
    EXPECT_EQ(o.errors.find("bad_alloc"), std::string::npos) << o.errors;
  }
  EXPECT_FALSE(fs::exists(out)) << "robophi run " << c.target << " wrote " << out;
}

INSTANTIATE_TEST_SUITE_P(Corpus, BrokenScene, ::testing::ValuesIn(readCases()), test::LabelName{});

// The table and the folder agree, and the corpus is as large as the issue asks.
TEST(BrokenSceneCorpus, EveryFileHasOneRowAndThereAreAtLeast150Cases) {
  const std::vector<BrokenCase> cases = readCases();
  EXPECT_GE(cases.size(), 150u);
  std::set<std::string> listed;
  for (const BrokenCase& c : cases) {
    if (!c.isScene()) continue;
    EXPECT_TRUE(listed.insert(c.target).second) << c.target << " has two rows";
    EXPECT_TRUE(fs::exists(kCorpus / c.target)) << c.target << " is listed but missing";
  }
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    const std::string name = entry.path().filename().string();
    if (name.ends_with(".json")) {
      EXPECT_TRUE(listed.contains(name)) << name << " has no row in expected.txt";
    }
  }
}

}  // namespace
}  // namespace robophi
