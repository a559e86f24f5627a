// robophi study ats: the paper's ATS-against-CTS comparison, as a table.
// robophi study experiments: the paper's experiments played from their scene files.
#include <fmt/format.h>

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "output/results_folder.h"
#include "record.h"
#include "robophi/version.h"
#include "run/interrupt.h"
#include "study_ats.h"
#include "study_experiments.h"

namespace robophi::cli {

namespace {

struct StudyArguments {
  std::string out;  // empty: print only; the study writes nothing but under --out
  std::int64_t maxCtsSteps = 50'000'000;
  std::string filter;
  std::string scenes = "scenes";
};

// After SIGINT or SIGTERM: nothing is written, the previous files stay as they were.
int interruptedExit(const char* command) {
  std::fprintf(stderr, "robophi %s: interrupted: nothing written, the previous files are kept\n",
               command);
  return exitCodeForSignal(InterruptGuard::caughtSignal());
}

int studyCommand(const StudyArguments& args) {
  InterruptGuard interrupt;
  std::vector<StudyRow> rows;
  std::vector<StudyCase> cases;
  try {
    cases = atsStudyCases(args.scenes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s (--scenes %s)\n", e.what(), args.scenes.c_str());
    return kExitBadInput;
  }
  for (const StudyCase& c : cases) {
    // --filter TEXT keeps the cases whose name holds TEXT; !TEXT the others.
    if (!args.filter.empty()) {
      const bool exclude = args.filter.front() == '!';
      const bool holds =
          c.name.find(exclude ? args.filter.substr(1) : args.filter) != std::string::npos;
      if (holds == exclude) continue;
    }
    std::fprintf(stderr, "robophi study ats: %s ...\n", c.name.c_str());
    rows.push_back(runStudyCase(c, args.maxCtsSteps));
    if (InterruptGuard::flag()) {
      // The files under --out hold the cases finished before the signal.
      std::fprintf(stderr,
                   "robophi study ats: interrupted: the files under --out hold the %zu case(s) "
                   "finished before it\n",
                   rows.size() > 0 ? rows.size() - 1 : 0);
      return exitCodeForSignal(InterruptGuard::caughtSignal());
    }
    const StudyRow& r = rows.back();
    std::printf(
        "%-40s ATS %7lld steps (%lld rejected) error %.3g | CTS dt %.3g %9lld steps "
        "error %.3g | steps x%.0f, cost per step x%.2f\n",
        r.caseName.c_str(), static_cast<long long>(r.ats.steps),
        static_cast<long long>(r.ats.rejected), r.ats.error, r.cts.dt,
        static_cast<long long>(r.cts.steps), r.cts.error, r.stepRatio, r.costPerStepRatio);
    std::fflush(stdout);
    // The files so far after every case (each replaced whole): a long study
    // stopped later still leaves what it measured.
    if (!args.out.empty()) writeAtsStudy(rows, args.out);
  }
  if (args.out.empty()) return kExitOk;
  writeAtsStudy(rows, args.out);
  std::printf("wrote ats-study.md, .csv and .svg under %s\n", args.out.c_str());
  return kExitOk;
}

struct ExperimentsArguments {
  std::string out;
  std::string filter;
  std::string record;
  std::string scenes;
};

// The folder the experiments' scene files are in: --scenes, else scenes/ in
// the working folder, else the checkout or installation the program belongs to
// (beside or above the executable). Empty after a message when there is none.
std::filesystem::path sceneFolder(const std::string& option, const std::string& probe) {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates;
  if (!option.empty()) {
    candidates.push_back(option);
  } else {
    candidates.push_back("scenes");
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const fs::path dir = exe.parent_path();
      for (const fs::path& c : {dir / "scenes", dir.parent_path() / "scenes",
                                dir.parent_path().parent_path() / "scenes",
                                dir.parent_path() / "share" / "robophi" / "scenes"})
        candidates.push_back(c);
    }
  }
  std::string looked;
  for (const fs::path& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c / probe, ec)) return c;
    looked += (looked.empty() ? "" : ", ") + c.string();
  }
  std::fprintf(stderr,
               "robophi study experiments: no scene folder holding %s (looked in %s): pass "
               "--scenes DIR (the repository's scenes/)\n",
               probe.c_str(), looked.c_str());
  return {};
}

int experimentsCommand(const ExperimentsArguments& args) {
  InterruptGuard interrupt;
  std::vector<Experiment> experiments = paperExperiments();
  // The scene files relative to their folder (see sceneFolder), not the working folder.
  std::string probe;
  for (const Experiment& e : experiments)
    if (probe.empty() && !e.scene.empty()) probe = std::filesystem::path(e.scene).filename();
  const std::filesystem::path scenes = sceneFolder(args.scenes, probe);
  if (scenes.empty()) return kExitBadInput;
  for (Experiment& e : experiments)
    if (!e.scene.empty()) e.scene = (scenes / std::filesystem::path(e.scene).filename()).string();
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  bool allOk = true, allLoaded = true;
  for (const Experiment& e : experiments) {
    if (!args.filter.empty() && e.id.find(args.filter) == std::string::npos &&
        e.title.find(args.filter) == std::string::npos)
      continue;
    if (!e.scene.empty())
      std::fprintf(stderr, "robophi study experiments: %s ...\n", e.scene.c_str());
    const ExperimentResult r = runExperiment(e, &InterruptGuard::flag());
    if (InterruptGuard::flag()) return interruptedExit("study experiments");
    allOk = allOk && r.ok();
    allLoaded = allLoaded && r.status != "load error";
    results.push_back(toJson(r));
    std::printf("%s\n", summaryLine(r).c_str());
    std::fflush(stdout);
  }
  if (results.empty()) {
    std::fprintf(stderr, "robophi study experiments: no experiment matches '%s'\n",
                 args.filter.c_str());
    return kExitBadInput;
  }

  nlohmann::ordered_json record = recordHeader();
  record["experiments"] = results;
  // experiments.json goes under --record, else under --out beside experiments.md.
  const std::string recordDir = !args.record.empty() ? args.record : args.out;
  const auto jsonPath = std::filesystem::path(recordDir) / "experiments.json";
  // A filtered run replaces only its own experiments in the record (and the table).
  if (!args.filter.empty() && !recordDir.empty()) {
    std::ifstream in(jsonPath);
    const nlohmann::ordered_json previous = nlohmann::ordered_json::parse(in, nullptr, false);
    if (!previous.is_discarded() && previous.contains("experiments")) {
      nlohmann::ordered_json merged = nlohmann::ordered_json::array();
      for (const Experiment& e : experiments) {  // the table's order
        const nlohmann::ordered_json* found = nullptr;
        for (const auto& r : results)
          if (r["id"] == e.id) found = &r;
        for (const auto& r : previous["experiments"])
          if (!found && r.value("id", std::string()) == e.id) found = &r;
        if (found) merged.push_back(*found);
      }
      record["experiments"] = merged;
    }
  }
  // Only experiments.json (under --record or --out) and experiments.md under
  // --out, each replaced whole or not at all; nothing without --out or --record.
  if (!recordDir.empty()) {
    output::writeFileAtomically(jsonPath,
                                [&](std::ostream& out) { out << record.dump(2) << '\n'; });
    std::printf("recorded in %s\n", jsonPath.string().c_str());
  }
  if (!args.out.empty()) {
    const auto mdPath = std::filesystem::path(args.out) / "experiments.md";
    output::writeFileAtomically(mdPath,
                                [&](std::ostream& out) { out << experimentsMarkdown(record); });
    std::printf("wrote %s\n", mdPath.string().c_str());
  }
  if (!allLoaded) return kExitBadInput;
  return allOk ? kExitOk : kExitDiverged;
}

}  // namespace

void addStudyCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("study", "Run a measured study");
  cmd->require_subcommand(1);
  auto args = std::make_shared<StudyArguments>();
  auto* ats = cmd->add_subcommand("ats", "Adaptive against constant step on analytic cases");
  ats->add_option("--out", args->out,
                  "Folder for ats-study.md, .csv and .svg (empty: print only; nothing else is "
                  "written)");
  ats->add_option("--scenes", args->scenes, "Folder of the experiment scenes (scenes/*.json)");
  ats->add_option("--max-cts-steps", args->maxCtsSteps, "Step budget of one CTS run");
  ats->add_option("--filter", args->filter,
                  "Only cases whose name contains this (!TEXT: only those that do not)");
  ats->callback([args, &exitCode] { exitCode = studyCommand(*args); });

  auto eargs = std::make_shared<ExperimentsArguments>();
  auto* experiments = cmd->add_subcommand(
      "experiments", "The paper's experiments from their scene files: outcomes and wall times");
  experiments->add_option("--out", eargs->out,
                          "Folder for experiments.md and experiments.json (e.g. docs); without "
                          "it: print only");
  experiments->add_option("--filter", eargs->filter,
                          "Only experiments whose id or title contains this");
  experiments->add_option("--record", eargs->record,
                          "Folder for experiments.json instead of --out (e.g. bench/results)");
  experiments->add_option("--scenes", eargs->scenes,
                          "Folder of the experiments' scene files (default: scenes/ here, or "
                          "the checkout beside the executable)");
  experiments->callback([eargs, &exitCode] { exitCode = experimentsCommand(*eargs); });
}

}  // namespace robophi::cli
