// robophi sweep SCENE --set POINTER=V1,V2 ... --out DIR: a batch study
// (docs/sweep.md). The runs are shared out over threads, and over MPI ranks
// when robophi is built with MPI and started by mpirun; rank 0 gathers the rows
// and writes one table, the same whatever the sharing.
#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <thread>

#include "commands.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "robophi/build/input_files.h"
#include "run/interrupt.h"
#include "sweep.h"

#ifdef ROBOPHI_HAVE_MPI
#include <mpi.h>
#endif

namespace robophi::cli {

namespace {

struct SweepArguments {
  std::string scene;
  std::vector<std::string> sets;
  int seeds = 0;
  double jitter = 0.01;
  double duration = 0.0;
  int threads = 0;
  std::vector<std::string> endObjects;
  std::string outDir;
  bool force = false;
  bool quiet = false;
};

// Started by an MPI launcher (mpirun, srun): how many processes it started.
int launchedProcesses() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* v = std::getenv(name)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  }
  return 1;
}

// The ranks of this process, MPI or not.
struct Ranks {
  int rank = 0;
  int size = 1;
  bool mpi = false;
};

#ifdef ROBOPHI_HAVE_MPI
// Gathers every rank's rows (run index → row) to rank 0.
void gatherRows(const Ranks& ranks, std::vector<nlohmann::json>& rows, std::vector<double>& wall) {
  nlohmann::json mine = nlohmann::json::array();
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(ranks.size)) == ranks.rank)
      mine.push_back({{"i", i}, {"row", rows[i]}, {"wall", wall[i]}});
  const std::string text = mine.dump();
  const int length = static_cast<int>(text.size());
  std::vector<int> lengths(static_cast<std::size_t>(ranks.size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<int> offsets(static_cast<std::size_t>(ranks.size), 0);
  int total = 0;
  for (int r = 0; r < ranks.size; ++r) {
    offsets[static_cast<std::size_t>(r)] = total;
    total += lengths[static_cast<std::size_t>(r)];
  }
  std::string all(ranks.rank == 0 ? static_cast<std::size_t>(total) : 0, '\0');
  MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
              0, MPI_COMM_WORLD);
  if (ranks.rank != 0) return;
  for (int r = 0; r < ranks.size; ++r) {
    const auto part = nlohmann::json::parse(
        all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                   static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)])));
    for (const auto& entry : part) {
      const auto i = entry.at("i").get<std::size_t>();
      rows[i] = entry.at("row");
      wall[i] = entry.at("wall").get<double>();
    }
  }
}
#endif

int sweepCommand(const SweepArguments& args, const Ranks& ranks) {
  const bool lead = ranks.rank == 0;
  const auto say = [&](const std::string& message) {
    if (lead) std::fprintf(stderr, "robophi sweep: %s\n", message.c_str());
  };
  SweepPlan plan;
  plan.scenePath = args.scene;
  plan.seeds = args.seeds;
  plan.jitter = args.jitter;
  plan.duration = args.duration;
  plan.endObjects = args.endObjects;
  try {
    for (const std::string& set : args.sets) plan.parameters.push_back(parseSweepParameter(set));
  } catch (const std::invalid_argument& e) {
    say(e.what());
    return kExitBadInput;
  }
  {
    std::string text;
    try {
      text = build::readInputFile(args.scene);  // a regular file, never a FIFO
    } catch (const build::InputFileError& e) {
      say(fmt::format("{}: cannot open the scene file: {}", args.scene, e.problem()));
      return kExitBadInput;
    }
    plan.scene = nlohmann::json::parse(text, nullptr, false, true);
    if (plan.scene.is_discarded() || !plan.scene.is_object()) {
      // The loader says where: report its diagnostics.
      SceneLoadResult loaded = loadSceneText(text, args.scene);
      for (const Diagnostic& d : loaded.errors)
        if (lead) std::fprintf(stderr, "%s\n", d.format("error").c_str());
      say(fmt::format("{}: not a scene (a JSON object); nothing was run or written", args.scene));
      return kExitBadInput;
    }
  }
  const std::vector<SweepCase> cases = sweepCases(plan);
  // Every case must load before anything runs: one message per case that does not.
  int bad = 0;
  for (const SweepCase& c : cases) {
    if (c.seed > 1) continue;  // the seeds of a combination share its scene
    std::string text;
    try {
      text = caseSceneText(plan, c);
    } catch (const std::invalid_argument& e) {
      say(e.what());
      return kExitBadInput;
    }
    SceneLoadResult loaded = loadSceneText(text, args.scene);
    if (loaded.ok()) {
      try {
        endStateObjects(loaded.scene->model, plan.endObjects);
      } catch (const std::invalid_argument& e) {
        say(fmt::format("{}; nothing was run or written", e.what()));
        return kExitBadInput;
      }
      continue;
    }
    ++bad;
    std::string where;
    for (std::size_t k = 0; k < plan.parameters.size(); ++k)
      where += fmt::format(" {}={}", plan.parameters[k].pointer,
                           plan.parameters[k].values[c.choice[k]].dump());
    for (const Diagnostic& d : loaded.errors)
      if (lead)
        std::fprintf(stderr, "robophi sweep: run %zu (%s): %s\n", c.index,
                     where.empty() ? "the scene" : where.substr(1).c_str(),
                     d.format("error").c_str());
  }
  if (bad > 0) {
    say(fmt::format("{} of {} runs have a scene that does not load; nothing was run or written",
                    bad, cases.size()));
    return kExitBadInput;
  }

  const std::filesystem::path out =
      args.outDir.empty() ? std::filesystem::path("out") /
                                (std::filesystem::path(args.scene).stem().string() + "-sweep")
                          : std::filesystem::path(args.outDir);
  const std::vector<std::string> files = {"sweep.csv", "sweep.json", "timing.csv", "report.html"};
  int folderOk = 1;
  std::optional<output::ResultsFolderLock> lock;  // the lead's, until the tables are in place
  if (lead) {
    std::string problem;
    try {
      lock.emplace(out);
      output::recoverResultsFolder(out);
      problem = output::resultsFolderProblem(out, "sweep", args.force, files);
    } catch (const std::exception& e) {
      problem = e.what();
    }
    if (!problem.empty()) {
      say(fmt::format("--out: {}; nothing was run or written", problem));
      folderOk = 0;
    }
  }
#ifdef ROBOPHI_HAVE_MPI
  if (ranks.mpi) MPI_Bcast(&folderOk, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  if (folderOk == 0) return kExitBadInput;

  const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
  const int threads = args.threads > 0 ? args.threads : static_cast<int>(hardware);
  if (!args.quiet)
    say(fmt::format("{} runs ({} combinations x {} seeds) on {} rank{} x {} thread{}", cases.size(),
                    cases.size() / static_cast<std::size_t>(std::max(1, plan.seeds)),
                    std::max(1, plan.seeds), ranks.size, ranks.size == 1 ? "" : "s", threads,
                    threads == 1 ? "" : "s"));
  // This rank's runs: every size-th, from its rank; threads take them in turn.
  std::vector<nlohmann::json> rows(cases.size());
  std::vector<double> wall(cases.size(), 0.0);
  std::vector<std::size_t> mine;
  for (std::size_t i = static_cast<std::size_t>(ranks.rank); i < cases.size();
       i += static_cast<std::size_t>(ranks.size))
    mine.push_back(i);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  const auto worker = [&] {
    for (std::size_t k = next++; k < mine.size(); k = next++) {
      if (InterruptGuard::flag().load()) return;
      const std::size_t i = mine[k];
      rows[i] = runCase(plan, cases[i], wall[i]);
      const std::size_t finished = ++done;
      if (!args.quiet && ranks.size == 1)
        std::fprintf(stderr, "robophi sweep: run %zu: %s (%zu of %zu)\n", i,
                     rows[i].value("status", std::string("?")).c_str(), finished, mine.size());
    }
  };
  {
    std::vector<std::thread> pool;
    const int n = std::min<int>(threads, static_cast<int>(std::max<std::size_t>(mine.size(), 1)));
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
  }
#ifdef ROBOPHI_HAVE_MPI
  if (ranks.mpi) gatherRows(ranks, rows, wall);
#endif
  if (!lead) return kExitOk;
  if (InterruptGuard::flag().load()) {
    say("interrupted: nothing was written");
    return exitCodeForSignal(InterruptGuard::caughtSignal() == 0 ? SIGINT
                                                                 : InterruptGuard::caughtSignal());
  }
  // Written beside the target and moved into place: never half a table.
  const std::filesystem::path staging = output::stagingFolderOf(out);
  try {
    std::filesystem::remove_all(staging);
    std::filesystem::create_directories(staging);
    output::writeResultsMarker(staging, "sweep", files);
    const std::string sharing =
        fmt::format("{} rank{} x {} thread{}", ranks.size, ranks.size == 1 ? "" : "s", threads,
                    threads == 1 ? "" : "s");
    writeSweepTables(staging.string(), plan, rows, wall, sharing);
    output::publishResultsFolder(staging, out, "sweep", args.force);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove_all(staging, ec);
    say(fmt::format("--out {}: {}", out.string(), e.what()));
    return kExitFailure;
  }
  std::map<std::string, int> statusCount;
  for (const nlohmann::json& row : rows) ++statusCount[row.value("status", std::string("?"))];
  std::string summary;
  for (const auto& [status, count] : statusCount) summary += fmt::format(", {} {}", status, count);
  std::printf("%s: %zu runs%s; table in %s\n", args.scene.c_str(), rows.size(), summary.c_str(),
              (out / "sweep.csv").string().c_str());
  return kExitOk;
}

}  // namespace

void addSweepCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "sweep",
      "Run a scene over every combination of parameter values (and seeds): one table, a report");
  auto args = std::make_shared<SweepArguments>();
  cmd->add_option("scene", args->scene, "Scene file (JSON)")->required();
  cmd->add_option("--set", args->sets,
                  "POINTER=V1,V2,...: the scene value at the JSON pointer takes each value in "
                  "turn (JSON values; repeat for more parameters: every combination runs)")
      ->take_all();
  cmd->add_option("--seeds", args->seeds,
                  "Runs per combination with seeds 1..N, each perturbing the initial positions "
                  "(counter-based); 0: the scene as written")
      ->check(CLI::Range(0, 1000000));
  cmd->add_option("--jitter", args->jitter,
                  "Perturbation per axis, as a fraction of each particle's radius (default 0.01)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--duration", args->duration, "Model time of every run (s), over the scene's")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", args->threads,
                  "Runs at once in this process (default: the cores available)")
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--end", args->endObjects,
                  "Objects whose end state (centre of mass, its speed) the table holds, by name "
                  "(comma-separated; none: no such columns; default: every object that touches "
                  "something, when there are at most 16)")
      ->delimiter(',');
  cmd->add_option("--out", args->outDir, "Results folder (default out/<scene name>-sweep)");
  cmd->add_flag("--force", args->force,
                "Also write into an --out folder that holds other files (they are kept)");
  cmd->add_flag("--quiet", args->quiet, "No progress lines");
  cmd->callback([args, &exitCode] {
    InterruptGuard interrupt;
    Ranks ranks;
    const int launched = launchedProcesses();
#ifdef ROBOPHI_HAVE_MPI
    if (launched > 1) {
      MPI_Init(nullptr, nullptr);
      MPI_Comm_rank(MPI_COMM_WORLD, &ranks.rank);
      MPI_Comm_size(MPI_COMM_WORLD, &ranks.size);
      ranks.mpi = true;
    }
#else
    if (launched > 1) {
      std::fprintf(stderr,
                   "robophi sweep: started as one of %d processes by an MPI launcher, but this "
                   "robophi was built without MPI (install libopenmpi-dev and rebuild); run it "
                   "without mpirun, with --threads\n",
                   launched);
      exitCode = kExitBadInput;
      return;
    }
#endif
    int code = sweepCommand(*args, ranks);
#ifdef ROBOPHI_HAVE_MPI
    if (ranks.mpi) {
      // Every rank exits with rank 0's verdict.
      MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
      MPI_Finalize();
    }
#endif
    exitCode = code;
  });
}

}  // namespace robophi::cli
