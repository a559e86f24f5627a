// The stress corpus (tests/scene/stress/, README.md there): valid but nasty
// scenes. Each row of expected.txt runs `robophi run SCENE EXTRAS` and asserts
// its exit code, that summary.json is valid JSON (no NaN), that a failure is
// named (status, failure_at: particle, object, time; stderr says it), and the
// row's physical checks on the run's outputs, so that no run ends with exit 0
// and a wrong answer.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "scene/scene_test_util.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kCorpus = fs::path(ROBOPHI_SOURCE_DIR) / "tests/scene/stress";

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return {};
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

// One row of expected.txt: `scene.json [extras] | exit | checks` (README.md).
struct StressCase {
  std::string label;
  std::string scene;   // a file of the folder
  std::string extras;  // command-line options after it
  int exitCode = 0;
  std::vector<std::string> checks;
  std::string knownFailure;  // the reason, for a case left as a known failure
  bool slow = false;
};

void PrintTo(const StressCase& c, std::ostream* out) {
  *out << c.scene << " " << c.extras << " | " << c.exitCode;
}

std::vector<std::string> splitChecks(const std::string& text) {
  // ';' separates checks, except inside "quotes".
  std::vector<std::string> checks;
  std::string current;
  bool quoted = false;
  for (const char ch : text) {
    if (ch == '"') quoted = !quoted;
    if (ch == ';' && !quoted) {
      if (!trim(current).empty()) checks.push_back(trim(current));
      current.clear();
    } else {
      current += ch;
    }
  }
  if (!trim(current).empty()) checks.push_back(trim(current));
  return checks;
}

std::vector<StressCase> readCases() {
  std::vector<StressCase> cases;
  std::ifstream in(kCorpus / "expected.txt");
  std::string line;
  std::set<std::string> labels;
  while (std::getline(in, line)) {
    if (trim(line).empty() || trim(line)[0] == '#') continue;
    const auto first = line.find('|');
    const auto second = first == std::string::npos ? first : line.find('|', first + 1);
    if (second == std::string::npos) {
      ADD_FAILURE() << "expected.txt: not 'scene [extras] | exit | checks': " << line;
      continue;
    }
    StressCase c;
    const std::string command = trim(line.substr(0, first));
    const auto space = command.find(' ');
    c.scene = command.substr(0, space);
    c.extras = space == std::string::npos ? "" : trim(command.substr(space));
    c.exitCode = std::atoi(trim(line.substr(first + 1, second - first - 1)).c_str());
    for (const std::string& check : splitChecks(line.substr(second + 1))) {
      if (check.starts_with("known-failure:")) {
        c.knownFailure = trim(check.substr(14));
      } else if (check == "slow") {
        c.slow = true;
      } else {
        c.checks.push_back(check);
      }
    }
    c.label = c.scene.substr(0, c.scene.size() - 5) + (c.extras.empty() ? "" : " " + c.extras);
    for (char& ch : c.label)
      if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    while (labels.contains(c.label)) c.label += "_";
    labels.insert(c.label);
    cases.push_back(c);
  }
  return cases;
}

std::vector<StressCase> casesOf(bool slow) {
  std::vector<StressCase> all = readCases(), some;
  std::copy_if(all.begin(), all.end(), std::back_inserter(some),
               [&](const StressCase& c) { return c.slow == slow; });
  return some;
}

// A CSV file as named columns.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
};

Table readCsv(const fs::path& path) {
  Table table;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return table;
  std::stringstream names(line);
  for (std::string name; std::getline(names, name, ',');) table.header.push_back(name);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');)
      row.push_back(cell.empty() ? std::nan("") : std::strtod(cell.c_str(), nullptr));
    table.rows.push_back(std::move(row));
  }
  return table;
}

// The outputs of one run, read on demand.
struct RunOutputs {
  fs::path dir;
  std::string errors;  // stderr
  json summary;
  json model;
  std::optional<Table> particles, objects, energy, contacts;
  const Table& get(std::optional<Table>& table, const char* name) {
    if (!table) table = readCsv(dir / name);
    return *table;
  }
};

// One row of values: a frame of particles.csv with its objects.csv rows, or a
// row of energy.csv. Fields are resolved by name (the check language, README.md).
class Rows {
 public:
  Rows(RunOutputs& run, bool energy) : run_(run), energy_(energy) {}
  std::size_t size() {
    return energy_ ? run_.get(run_.energy, "energy.csv").rows.size()
                   : run_.get(run_.particles, "particles.csv").rows.size();
  }
  double time(std::size_t row) { return field(row, "t"); }

  double field(std::size_t row, const std::string& name) {
    if (energy_) {
      const Table& e = run_.get(run_.energy, "energy.csv");
      const std::string column = name == "t" ? "t" : name.substr(2);
      if (name != "t" && !name.starts_with("E."))
        throw std::runtime_error("'" + name + "' is not a column of energy.csv (E.<column>)");
      const int c = e.column(column);
      if (c < 0) throw std::runtime_error("energy.csv has no column '" + column + "'");
      return e.rows.at(row).at(static_cast<std::size_t>(c));
    }
    const Table& p = run_.get(run_.particles, "particles.csv");
    const std::vector<double>& frame = p.rows.at(row);
    if (name == "t") return frame.at(0);
    const auto dot = name.find('.');
    if (dot == std::string::npos) throw std::runtime_error("no field in '" + name + "'");
    const std::string who = name.substr(0, dot), what = name.substr(dot + 1);
    auto particleValue = [&](std::size_t i, const std::string& f) {
      if (f == "speed") {
        const double vx = particleValue_(frame, p, i, "vx"), vy = particleValue_(frame, p, i, "vy"),
                     vz = particleValue_(frame, p, i, "vz");
        return std::sqrt(vx * vx + vy * vy + vz * vz);
      }
      return particleValue_(frame, p, i, f);
    };
    if (who.size() > 1 && who[0] == 'p' &&
        std::all_of(who.begin() + 1, who.end(), [](char ch) { return std::isdigit(ch); }))
      return particleValue(std::stoul(who.substr(1)), what);
    const json& masses = run_.model.at("particles").at("mass");
    if (who == "P") {  // total momentum
      double sum = 0.0;
      for (std::size_t i = 0; i < masses.size(); ++i)
        sum += masses[i].get<double>() * particleValue(i, "v" + what);
      return sum;
    }
    // An object by name: objects.csv's columns, or extremes over its particles.
    const json& objects = run_.model.at("objects");
    for (std::size_t o = 0; o < objects.size(); ++o) {
      if (objects[o].at("name") != who) continue;
      const auto first = objects[o].at("first").get<std::size_t>();
      const auto count = objects[o].at("count").get<std::size_t>();
      if (what.size() == 4 && (what.ends_with("min") || what.ends_with("max"))) {
        const bool low = what.ends_with("min");
        double best = low ? std::numeric_limits<double>::infinity()
                          : -std::numeric_limits<double>::infinity();
        for (std::size_t i = first; i < first + count; ++i) {
          const double v = particleValue(i, what.substr(0, 1));
          best = low ? std::min(best, v) : std::max(best, v);
        }
        return best;
      }
      const Table& table = run_.get(run_.objects, "objects.csv");
      const int c = table.column(what);
      if (c < 0) throw std::runtime_error("objects.csv has no column '" + what + "'");
      // Rows of objects.csv at this frame's time, one per object, then -1.
      const double t = frame.at(0);
      for (const auto& r : table.rows)
        if (r.at(0) == t && r.at(1) == static_cast<double>(o))
          return r.at(static_cast<std::size_t>(c));
      throw std::runtime_error("objects.csv has no row for object '" + who +
                               "' at t = " + std::to_string(t));
    }
    throw std::runtime_error("'" + who + "' is neither p<index>, P nor an object of model.json");
  }

 private:
  static double particleValue_(const std::vector<double>& frame, const Table& p, std::size_t i,
                               const std::string& f) {
    const int c = p.column(f + std::to_string(i));
    if (c < 0)
      throw std::runtime_error("particles.csv has no column '" + f + std::to_string(i) + "'");
    return frame.at(static_cast<std::size_t>(c));
  }
  RunOutputs& run_;
  bool energy_;
};

// The check language's expressions (README.md): numbers, + - * /, abs, sqrt,
// summary(/json/pointer), count(contacts), and start/end/min/max(EXPR) over the
// rows (optionally @t0:t1) of particles.csv+objects.csv, or of energy.csv when
// EXPR names E.<column>.
class Parser {
 public:
  Parser(std::string text, RunOutputs& run) : text_(std::move(text)), run_(run) {}

  double expression() {
    double value = term();
    for (;;) {
      skip();
      if (peek('+')) {
        ++at_;
        value += term();
      } else if (peek('-')) {
        ++at_;
        value -= term();
      } else {
        return value;
      }
    }
  }
  void skip() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
  }
  bool peek(char ch) {
    skip();
    return at_ < text_.size() && text_[at_] == ch;
  }
  bool take(const std::string& word) {
    skip();
    if (text_.compare(at_, word.size(), word) != 0) return false;
    at_ += word.size();
    return true;
  }
  void expect(char ch) {
    if (!peek(ch)) fail(std::string("expected '") + ch + "'");
    ++at_;
  }
  bool atEnd() {
    skip();
    return at_ >= text_.size();
  }
  std::string rest() {
    skip();
    return text_.substr(at_);
  }
  std::string word() {
    skip();
    const std::size_t begin = at_;
    while (at_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[at_])) ||
                                  text_[at_] == '_' || text_[at_] == '.' || text_[at_] == '/'))
      ++at_;
    return text_.substr(begin, at_ - begin);
  }
  double number() {
    skip();
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) fail("expected a number");
    at_ += static_cast<std::size_t>(end - begin);
    return v;
  }
  [[noreturn]] void fail(const std::string& what) {
    throw std::runtime_error(what + " at '" + text_.substr(std::min(at_, text_.size())) + "'");
  }

 private:
  double term() {
    double value = factor();
    for (;;) {
      skip();
      if (peek('*')) {
        ++at_;
        value *= factor();
      } else if (peek('/')) {
        ++at_;
        value /= factor();
      } else {
        return value;
      }
    }
  }

  double factor() {
    skip();
    if (peek('-')) {
      ++at_;
      return -factor();
    }
    if (peek('(')) {
      ++at_;
      const double v = expression();
      expect(')');
      return v;
    }
    if (at_ < text_.size() &&
        (std::isdigit(static_cast<unsigned char>(text_[at_])) || text_[at_] == '.'))
      return number();
    const std::string name = word();
    if (name == "abs" || name == "sqrt") {
      expect('(');
      const double v = expression();
      expect(')');
      return name == "abs" ? std::abs(v) : std::sqrt(v);
    }
    if (name == "summary") {
      expect('(');
      const std::string pointer = word();
      expect(')');
      const json& value = run_.summary.at(json::json_pointer(pointer));
      if (!value.is_number()) fail("summary " + pointer + " is not a number: " + value.dump());
      return value.get<double>();
    }
    if (name == "count") {
      expect('(');
      if (word() != "contacts") fail("count(contacts) only");
      expect(')');
      return static_cast<double>(run_.get(run_.contacts, "contacts.csv").rows.size());
    }
    if (name == "start" || name == "end" || name == "min" || name == "max") return series(name);
    if (row_) return rows_->field(*row_, name);
    fail("'" + name + "' outside start/end/min/max(...)");
  }

  // start/end/min/max over rows, within the window @t0:t1 when given.
  double series(const std::string& reduce) {
    double from = -std::numeric_limits<double>::infinity();
    double to = std::numeric_limits<double>::infinity();
    if (peek('@')) {
      ++at_;
      from = number();
      expect(':');
      to = number();
    }
    expect('(');
    const std::size_t begin = at_;
    // Which table: energy.csv when the expression names E.<column>.
    int depth = 1;
    std::size_t end = begin;
    for (; end < text_.size() && depth > 0; ++end) {
      if (text_[end] == '(') ++depth;
      if (text_[end] == ')') --depth;
    }
    const std::string inner = text_.substr(begin, end - 1 - begin);
    Rows rows(run_, inner.find("E.") != std::string::npos);
    std::vector<double> values;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const double t = rows.time(r);
      if (t < from - 1e-12 || t > to + 1e-12) continue;
      Parser sub(inner, run_);
      sub.rows_ = &rows;
      sub.row_ = r;
      values.push_back(sub.expression());
      if (!sub.atEnd()) sub.fail("unexpected text");
    }
    at_ = end;
    if (values.empty()) fail("no rows for " + reduce + "(" + inner + ")");
    if (reduce == "start") return values.front();
    if (reduce == "end") return values.back();
    if (reduce == "min") return *std::min_element(values.begin(), values.end());
    return *std::max_element(values.begin(), values.end());
  }

  std::string text_;
  std::size_t at_ = 0;
  RunOutputs& run_;
  Rows* rows_ = nullptr;
  std::optional<std::size_t> row_;
};

// One check: `EXPR OP EXPR`, `EXPR in [A, B]`, `EXPR ~ EXPR ± TOL[%]`,
// `stderr has "text"`, `warning has "text"`, `summary(/ptr) = word`.
// Returns "" when it holds, else what was found.
std::string evaluateCheck(const std::string& check, RunOutputs& run) {
  auto quoted = [&](const std::string& text) {
    const auto a = text.find('"'), b = text.rfind('"');
    if (a == std::string::npos || b <= a) throw std::runtime_error("expected \"text\"");
    return text.substr(a + 1, b - a - 1);
  };
  if (check.starts_with("stderr has")) {
    const std::string text = quoted(check);
    return run.errors.find(text) != std::string::npos ? "" : "stderr lacks it:\n" + run.errors;
  }
  if (check.starts_with("warning has")) {
    const std::string text = quoted(check);
    for (const json& w : run.summary.value("warnings", json::array()))
      if (w.is_string() && w.get<std::string>().find(text) != std::string::npos) return "";
    return "no warning says it: " + run.summary.value("warnings", json::array()).dump();
  }
  Parser p(check, run);
  if (check.starts_with("summary(") && check.find(") =") != std::string::npos &&
      check.find('"') == std::string::npos && check.find_first_of("<>~") == std::string::npos) {
    const auto close = check.find(')');
    const std::string pointer = trim(check.substr(8, close - 8));
    const std::string want = trim(check.substr(check.find('=', close) + 1));
    const json& value = run.summary.at(json::json_pointer(pointer));
    const std::string got = value.is_string() ? value.get<std::string>() : value.dump();
    return got == want ? "" : "got " + got;
  }
  const double left = p.expression();
  std::ostringstream found;
  found.precision(10);
  found << "left side = " << left;
  if (p.take("in")) {
    p.expect('[');
    const double low = p.expression();
    p.expect(',');
    const double high = p.expression();
    p.expect(']');
    if (!p.atEnd()) p.fail("unexpected text");
    return left >= low && left <= high ? "" : found.str();
  }
  if (p.take("~")) {
    const double centre = p.expression();
    if (!p.take("±") && !p.take("+-")) p.fail("expected ± after ~ EXPR");
    double tolerance = p.number();
    if (p.take("%")) tolerance *= 0.01 * std::abs(centre);
    if (!p.atEnd()) p.fail("unexpected text");
    found << ", expected " << centre << " ± " << tolerance;
    return std::abs(left - centre) <= tolerance ? "" : found.str();
  }
  for (const std::string op : {"<=", ">=", "<", ">"}) {
    if (!p.take(op)) continue;
    const double right = p.expression();
    if (!p.atEnd()) p.fail("unexpected text");
    found << ", right side = " << right;
    const bool holds = op == "<="   ? left <= right
                       : op == ">=" ? left >= right
                       : op == "<"  ? left < right
                                    : left > right;
    return holds ? "" : found.str();
  }
  p.fail("expected <, <=, >, >=, in [a, b] or ~ x ± tol");
}

struct StressOutcome {
  int exitCode = -1;
  std::string errors;
  double wallSeconds = 0.0;
};

StressOutcome robophi(const std::string& args, const fs::path& scratch) {
  const fs::path errors = scratch / "stderr.txt";
  const std::string command =
      std::string(ROBOPHI_BINARY) + " " + args + " > /dev/null 2> " + errors.string();
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, testing::readText(errors), wall};
}

class StressScene : public ::testing::TestWithParam<StressCase> {
 protected:
  void SetUp() override { scratch_ = testing::makeTempFolder("robophi_stress_"); }
  void TearDown() override { fs::remove_all(scratch_); }
  fs::path scratch_;
};

TEST_P(StressScene, EndsSoundOrWithANamedFailure) {
  const StressCase& c = GetParam();
  if (!c.knownFailure.empty()) GTEST_SKIP() << "known failure: " << c.knownFailure;
  const fs::path scene = kCorpus / c.scene;
  ASSERT_TRUE(fs::exists(scene)) << scene;
  RunOutputs run;
  run.dir = scratch_ / "out";
  const StressOutcome o = robophi(
      "run " + scene.string() + " " + c.extras + " --quiet --out " + run.dir.string(), scratch_);
  run.errors = o.errors;
  RecordProperty("wall_seconds", std::to_string(o.wallSeconds));
  ASSERT_EQ(o.exitCode, c.exitCode) << o.errors;
  EXPECT_EQ(o.errors.find("bad_alloc"), std::string::npos) << o.errors;
  if (c.exitCode == 2) {
    // Bad input: a message, nothing run or written.
    EXPECT_FALSE(o.errors.empty());
    EXPECT_FALSE(fs::exists(run.dir)) << "robophi run " << c.extras << " wrote " << run.dir;
  } else {
    // summary.json is JSON (a NaN would not parse) and its status fits the exit code.
    const std::string summaryText = testing::readText(run.dir / "summary.json");
    ASSERT_NO_THROW(run.summary = json::parse(summaryText)) << summaryText;
    ASSERT_NO_THROW(run.model = json::parse(testing::readText(run.dir / "model.json")));
    const std::string status = run.summary.at("status").get<std::string>();
    const std::map<int, std::set<std::string>> statuses = {{0, {"ok"}},
                                                           {3, {"diverged", "stalled"}},
                                                           {4, {"energy_account_broken"}},
                                                           {5, {"goal_not_reached"}}};
    ASSERT_TRUE(statuses.contains(c.exitCode)) << "no status for exit " << c.exitCode;
    EXPECT_TRUE(statuses.at(c.exitCode).contains(status)) << status;
    if (c.exitCode != 0) {
      // The failure is named in summary.json and on stderr.
      const std::string failure = run.summary.value("failure", "");
      EXPECT_FALSE(failure.empty());
      EXPECT_NE(o.errors.find(failure.substr(0, 60)), std::string::npos)
          << "stderr does not say '" << failure << "':\n"
          << o.errors;
    }
    if (c.exitCode == 3 || c.exitCode == 4) {
      // Where: the time, the step, the particle and its object (for a broken
      // energy account: where it first passed its bound, the most energetic one).
      const json& at = run.summary.at("failure_at");
      EXPECT_TRUE(at.at("time_s").is_number()) << at.dump();
      EXPECT_TRUE(at.at("particle").is_number_integer()) << at.dump();
      EXPECT_TRUE(at.at("object").is_string()) << at.dump();
      if (at.at("particle").is_number_integer()) {
        const std::string particle = "particle " + at.at("particle").dump();
        EXPECT_NE(o.errors.find(particle), std::string::npos) << o.errors;
      }
    }
  }
  for (const std::string& check : c.checks) {
    SCOPED_TRACE(check);
    try {
      const std::string problem = evaluateCheck(check, run);
      EXPECT_TRUE(problem.empty()) << "check fails: " << check << "\n" << problem;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "check '" << check << "' cannot be evaluated: " << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Corpus, StressScene, ::testing::ValuesIn(casesOf(false)),
                         test::LabelName{});
// Rows marked `slow` (over ~5 s): ctest label "slow" (tests/CMakeLists.txt).
INSTANTIATE_TEST_SUITE_P(Slow, StressScene, ::testing::ValuesIn(casesOf(true)), test::LabelName{});
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(StressScene);

// The table and the folder agree, and the corpus is as large as the issue asks.
TEST(StressSceneCorpus, EveryFileHasARowAndThereAreAtLeast36Scenes) {
  const std::vector<StressCase> cases = readCases();
  std::set<std::string> listed;
  for (const StressCase& c : cases) {
    listed.insert(c.scene);
    EXPECT_TRUE(fs::exists(kCorpus / c.scene)) << c.scene << " is listed but missing";
    EXPECT_TRUE(c.exitCode != 0 || !c.checks.empty() || !c.knownFailure.empty())
        << c.label << ": an exit 0 row needs a physical check";
  }
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    const std::string name = entry.path().filename().string();
    if (!name.ends_with(".json")) continue;
    ++files;
    EXPECT_TRUE(listed.contains(name)) << name << " has no row in expected.txt";
  }
  EXPECT_GE(files, 36u);
}

}  // namespace
}  // namespace robophi
