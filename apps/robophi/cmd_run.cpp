// robophi run SCENE: simulate and write the results folder (docs/output-format.md).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <optional>

#include "commands.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "robotics/tasks.h"
#include "run/interrupt.h"
#include "run/live_view.h"
#include "run/runner.h"
#include "run/start_checks.h"
#include "scene_input.h"

namespace robophi::cli {

namespace {

struct RunArguments {
  std::string scene;
  std::string outDir;
  bool force = false;
  // Numbers as typed, checked by positiveNumber (a clear message, exit 2).
  std::optional<std::string> duration, dt, fps, energyRate;
  std::optional<std::string> tolerance, minStep, maxStep, maxPenetration;
  std::optional<std::string> checkpointEvery, stopAfter;
  std::string integrator;
  std::string stepMode;
  bool quiet = false;
  int threads = 0;        // of the step; 0: the cores available
  UrdfSceneOptions urdf;  // a bare URDF (docs/robots.md)
  std::string base;
  // The live view (docs/viewer.md "Live view").
  bool live = false;
  int livePort = LiveViewSettings{}.port;
  std::optional<std::string> liveWait;
};

// `text` as a positive finite number, or a message on stderr and nullopt.
std::optional<double> positiveNumber(const char* option, const std::string& text,
                                     const char* meaning) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !(value > 0.0) || !std::isfinite(value)) {
    std::fprintf(stderr, "robophi run: %s '%s': expected a positive number (%s)\n", option,
                 text.c_str(), meaning);
    return std::nullopt;
  }
  return value;
}

// Sets `target` from an option when it was given; false after a bad value.
bool setFromOption(const char* option, const std::optional<std::string>& text, const char* meaning,
                   double& target) {
  if (!text) return true;
  const auto value = positiveNumber(option, *text, meaning);
  if (value) target = *value;
  return value.has_value();
}

// Where a RunSettings field came from: its option as typed, or the scene's key.
std::string settingSource(const std::string& field, const RunArguments& args) {
  const auto from = [](const char* option, const std::optional<std::string>& text,
                       const char* key) {
    return text ? fmt::format("{} {}", option, *text) : fmt::format("the scene's {}", key);
  };
  if (field == "dt") return from("--dt", args.dt, "run.dt");
  if (field == "fps") return from("--fps", args.fps, "run.fps");
  if (field == "energyRate") return from("--energy-rate", args.energyRate, "duration");
  return from("--duration", args.duration, "run.duration");
}

// A progress bar on a terminal; otherwise a status line every 10 s of wall time.
std::function<void(const RunProgress&)> makeProgress(bool quiet) {
  if (quiet) return {};
  const bool terminal = isatty(fileno(stderr)) != 0;
  auto lastLine = std::make_shared<double>(0.0);
  return [terminal, lastLine](const RunProgress& p) {
    const double fraction = p.duration > 0.0 ? std::min(1.0, p.simulatedTime / p.duration) : 1.0;
    if (terminal) {
      constexpr int kWidth = 40;
      const int filled = static_cast<int>(fraction * kWidth);
      std::fprintf(stderr, "\r[%s%s] %5.1f%%  t=%.4g s  %lld steps  %.1f s wall",
                   std::string(static_cast<std::size_t>(filled), '#').c_str(),
                   std::string(static_cast<std::size_t>(kWidth - filled), '.').c_str(),
                   100.0 * fraction, p.simulatedTime, static_cast<long long>(p.steps),
                   p.wallSeconds);
      std::fflush(stderr);
    } else if (p.wallSeconds - *lastLine >= 10.0) {
      *lastLine = p.wallSeconds;
      std::fprintf(stderr, "robophi: %.1f%% t=%.4g s of %.4g s, %lld steps, %.1f s wall\n",
                   100.0 * fraction, p.simulatedTime, p.duration, static_cast<long long>(p.steps),
                   p.wallSeconds);
    }
  };
}

int runCommand(const RunArguments& args) {
  // From here on SIGINT and SIGTERM end the run cleanly, with its results so far.
  InterruptGuard interrupt;
  auto scene = loadInputOrReport("run", args.scene, args.urdf, args.base);
  if (!scene) return kExitBadInput;

  RunOptions options;
  options.settings = scene->run;
  options.urdf = args.urdf;  // kept in checkpoints, for resume
  urdfOptionsOk("run", args.base, options.urdf);
  options.threads = args.threads;
  // The command line overrides the scene's run settings (the model is built:
  // --dt is the step only, it changes no stiffness).
  RunSettings& run = options.settings;
  AdaptiveStepSettings& adaptive = run.adaptive;
  const bool numbersOk =
      setFromOption("--duration", args.duration, "model time to simulate, s", run.duration) &&
      setFromOption("--dt", args.dt, "step, s", run.dt) &&
      setFromOption("--fps", args.fps, "frames per model second", run.fps) &&
      setFromOption("--energy-rate", args.energyRate, "energy rows per model second",
                    options.energyRate) &&
      setFromOption("--tolerance", args.tolerance, "adaptive step's energy tolerance, -",
                    adaptive.energyTolerance) &&
      setFromOption("--min-step", args.minStep, "adaptive step's floor, s", adaptive.minStep) &&
      setFromOption("--max-step", args.maxStep, "adaptive step's ceiling, s", adaptive.maxStep) &&
      setFromOption("--max-penetration", args.maxPenetration,
                    "penetration growth per step, fraction of the radius, -",
                    adaptive.maxPenetrationFraction) &&
      setFromOption("--checkpoint-every", args.checkpointEvery, "model time between checkpoints, s",
                    options.checkpointEvery) &&
      setFromOption("--stop-after", args.stopAfter, "model time to stop at with a checkpoint, s",
                    options.stopAfter);
  if (!numbersOk) return kExitBadInput;
  if (adaptive.minStep > adaptive.maxStep) {
    std::fprintf(stderr,
                 "robophi run: the adaptive step's floor %g s (--min-step, run.adaptive.minStep) "
                 "is above its ceiling %g s (--max-step, run.adaptive.maxStep)\n",
                 adaptive.minStep, adaptive.maxStep);
    return kExitBadInput;
  }
  if (!args.integrator.empty() && !parseIntegrator(args.integrator, options.settings.integrator)) {
    std::fprintf(stderr, "robophi run: --integrator '%s': expected taylor, symplectic or verlet\n",
                 args.integrator.c_str());
    return kExitBadInput;
  }
  if (args.stepMode == "constant") {
    options.settings.stepMode = StepMode::kConstant;
  } else if (args.stepMode == "adaptive") {
    options.settings.stepMode = StepMode::kAdaptive;
  } else if (!args.stepMode.empty()) {
    std::fprintf(stderr, "robophi run: --step '%s': expected adaptive or constant\n",
                 args.stepMode.c_str());
    return kExitBadInput;
  }
  // The numbers together: dt within the duration, and steps and rows within the limits.
  if (const auto problem = checkRunSettings(options.settings, options.energyRate)) {
    std::fprintf(stderr, "robophi run: %s: %s; nothing was run or written\n",
                 settingSource(problem->field, args).c_str(), problem->message.c_str());
    return kExitBadInput;
  }
  options.outDir =
      args.outDir.empty()
          ? (std::filesystem::path("out") / std::filesystem::path(args.scene).stem()).string()
          : args.outDir;
  options.force = args.force;
  // The folder is this run's from here (runScene takes the lock again): another
  // robophi writing it is refused before anything is looked at.
  std::optional<output::ResultsFolderLock> lock;
  try {
    lock.emplace(options.outDir);
  } catch (const output::ResultsFolderError& e) {
    std::fprintf(stderr, "robophi run: --out: %s; nothing was run or written\n", e.what());
    return kExitBadInput;
  }
  if (const std::string problem = outputFolderProblem(options); !problem.empty()) {
    std::fprintf(stderr,
                 "robophi run: --out: %s. robophi deletes nothing it did not write: choose "
                 "another --out or move those away%s; nothing was run or written\n",
                 problem.c_str(),
                 args.force ? "" : ", or pass --force to write robophi's files beside them");
    return kExitBadInput;
  }
  options.progress = makeProgress(args.quiet);
  options.tasks = {robotics::makeSceneTasks(*scene)};  // the scene's robotics section
  options.stop = &InterruptGuard::flag();
  // The live view: a task after the scene's (it sees their edits, and its drag
  // is booked apart from theirs).
  std::shared_ptr<LiveView> live;
  if (args.live) {
    LiveViewSettings liveSettings;
    liveSettings.port = args.livePort;
    if (args.liveWait && *args.liveWait == "0") {
      liveSettings.waitSeconds = 0.0;
    } else if (!setFromOption("--live-wait", args.liveWait, "wall seconds to wait for a viewer",
                              liveSettings.waitSeconds)) {
      return kExitBadInput;
    }
    try {
      live = std::make_shared<LiveView>(*scene, scene->initial, liveSettings, options.stop);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "robophi run: --live: %s; nothing was run or written\n", e.what());
      return kExitBadInput;
    }
    std::fprintf(stderr, "robophi: live view at %s (waiting up to %g s for a viewer)\n",
                 live->url().c_str(), liveSettings.waitSeconds);
    std::fflush(stderr);
    options.tasks.push_back(StepTask(std::shared_ptr<Task>(live)));
  }

  const StabilityEstimate stability = estimateStability(scene->model, &scene->initial.position);
  if (const std::string problem = adaptiveStepLimitProblem(options.settings, stability);
      !problem.empty()) {
    std::fprintf(stderr, "robophi run: %s: %s; nothing was run or written\n", args.scene.c_str(),
                 problem.c_str());
    return kExitBadInput;
  }
  if (!args.quiet) std::fprintf(stderr, "%s\n", describeScene(*scene, stability).c_str());
  for (const auto& w : preflightWarnings(options.settings, stability)) {
    std::fprintf(stderr, "%s: warning: %s\n", args.scene.c_str(), w.c_str());
  }
  for (const auto& w : startingOverlapWarnings(scene->model, scene->initial)) {
    std::fprintf(stderr, "%s: warning: %s\n", args.scene.c_str(), w.c_str());
  }

  RunReport report;
  State finalState;  // (the live view's last frame)
  try {
    report = runScene(*scene, options, live ? &finalState : nullptr);
  } catch (const output::ResultsFolderError& e) {  // another run holds it, or it changed
    std::fprintf(stderr, "robophi run: --out: %s\n", e.what());
    return kExitBadInput;
  } catch (const output::WriteError& e) {  // a full disk: the earlier results as they were
    std::fprintf(stderr, "robophi run: %s\n", e.what());
    return kExitFailure;
  }
  if (live) live->finish(&finalState);
  if (!args.quiet && isatty(fileno(stderr))) std::fprintf(stderr, "\n");
  return reportRun(args.scene, options, report);
}

}  // namespace

namespace {

// What set most of an adaptive run's steps, as "; 96% set by the contacts'
// stability" (empty without steps).
std::string mostlySetBy(const AdaptiveStepStats& a) {
  const StepCause* most =
      std::max_element(std::begin(kStepCauses), std::end(kStepCauses),
                       [&](const StepCause& x, const StepCause& y) { return a.*x.count < a.*y.count; });
  const std::int64_t count = a.*most->count;
  if (a.accepted <= 0 || count <= 0) return {};
  return fmt::format("; {:.0f}% set by {}",
                     100.0 * static_cast<double>(count) / static_cast<double>(a.accepted),
                     most->words);
}

}  // namespace

int reportRun(const std::string& label, const RunOptions& options, const RunReport& report) {
  const std::string steps =
      options.settings.stepMode == StepMode::kAdaptive
          ? fmt::format("{} adaptive steps ({} rejected, dt {:.3g} to {:.3g} s{})",
                        report.adaptive.accepted, report.adaptive.rejected,
                        report.adaptive.smallestStep, report.adaptive.largestStep,
                        mostlySetBy(report.adaptive))
          : fmt::format("{} constant steps of {:.3g} s", report.steps, options.settings.dt);
  std::printf("%s: %s, %s, %s; %.4g s simulated in %.3f s wall, energy drift %.3g; results in %s\n",
              label.c_str(), report.status.c_str(), steps.c_str(),
              integratorName(options.settings.integrator), report.simulatedTime, report.wallSeconds,
              report.energyDrift, options.outDir.c_str());
  // Warnings the run adds after its summary (a replay page it could not make, a
  // constant step past the drives' damping limit).
  for (const std::string& w : report.warnings) {
    if (w.starts_with("replay.html not written:") || w.find("joint drives' damping") != w.npos)
      std::fprintf(stderr, "%s: warning: %s\n", label.c_str(), w.c_str());
  }
  if (report.status == "stopped") {
    std::fprintf(stderr,
                 "%s: stopped at t = %.6g s with a checkpoint: robophi resume %s continues\n",
                 label.c_str(), report.simulatedTime, options.outDir.c_str());
    return kExitOk;
  }
  if (report.interrupted()) {
    const int caught = InterruptGuard::caughtSignal();
    std::fprintf(
        stderr,
        "%s: interrupted by %s at t = %.6g s: the results so far are in %s "
        "(summary.json \"status\": \"interrupted\")%s\n",
        label.c_str(), caught == SIGTERM ? "SIGTERM" : "SIGINT", report.simulatedTime,
        options.outDir.c_str(),
        report.checkpoints > 0 ? "; robophi resume continues from its last checkpoint" : "");
    return exitCodeForSignal(caught == 0 ? SIGINT : caught);
  }
  if (report.ok()) return kExitOk;
  std::fprintf(stderr, "%s: error: %s\n", label.c_str(), report.failure.c_str());
  if (report.status == "energy_account_broken") return kExitEnergyAccount;
  if (report.status == "goal_not_reached") return kExitGoalNotReached;
  return kExitDiverged;
}

void addRunCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("run", "Simulate a scene and write its results folder");
  auto args = std::make_shared<RunArguments>();
  cmd->add_option("scene", args->scene, "Scene file (JSON) or a URDF robot (.urdf)")->required();
  addUrdfOptions(*cmd, args->urdf, args->base);
  cmd->add_option("--out", args->outDir,
                  "Results folder (default out/<scene name>); an existing one must hold nothing "
                  "but robophi's results (its robophi-results.json lists them)");
  cmd->add_flag("--force", args->force,
                "Also write into an --out folder that holds other files: they are kept, only "
                "robophi's own files are replaced");
  cmd->add_option("--duration", args->duration, "Model time to simulate (s)")->type_name("NUMBER");
  cmd->add_option("--step", args->stepMode,
                  "adaptive (energy-based, the default) | constant (use --dt)");
  cmd->add_option("--dt", args->dt,
                  "Constant time step, or the first adaptive trial step (s); the step only, "
                  "never a stiffness")
      ->type_name("NUMBER");
  cmd->add_option("--integrator", args->integrator, "taylor | symplectic | verlet");
  cmd->add_option("--fps", args->fps, "Frames per model second in particles.csv (default 60)")
      ->type_name("NUMBER");
  cmd->add_option("--energy-rate", args->energyRate,
                  "Rows of energy.csv per model second (default 1000)")
      ->type_name("NUMBER");
  // The adaptive step's settings (AdaptiveStepSettings), over the scene's run.adaptive.
  const AdaptiveStepSettings defaults;
  const std::string group =
      "Adaptive step (docs/adaptive-step.md; each overrides the scene's run.adaptive key)";
  cmd->add_option("--tolerance", args->tolerance,
                  fmt::format("Accepted energy error per step, relative to the energy scale (-; "
                              "energyTolerance, default {:g})",
                              defaults.energyTolerance))
      ->group(group)
      ->type_name("NUMBER");
  cmd->add_option("--min-step", args->minStep,
                  fmt::format("Smallest step (s; minStep, default {:g}: 1e-8 x the first trial "
                              "step): below it the run stops as stalled",
                              defaults.minStep))
      ->group(group)
      ->type_name("NUMBER");
  cmd->add_option("--max-step", args->maxStep,
                  fmt::format("Largest step (s; maxStep, default {:g}: no ceiling)",
                              defaults.maxStep))
      ->group(group)
      ->type_name("NUMBER");
  cmd->add_option("--max-penetration", args->maxPenetration,
                  fmt::format("Largest growth of the deepest contact in one step, as a fraction "
                              "of the smaller radius (-; maxPenetrationFraction, default {:g})",
                              defaults.maxPenetrationFraction))
      ->group(group)
      ->type_name("NUMBER");
  cmd->add_option("--checkpoint-every", args->checkpointEvery,
                  "Write a checkpoint (checkpoint.json in the results folder) every S model "
                  "seconds; robophi resume DIR continues from the last one")
      ->type_name("S");
  cmd->add_option("--stop-after", args->stopAfter,
                  "Stop at model time S with a checkpoint (status \"stopped\", exit 0)")
      ->type_name("S");
  cmd->add_option("--threads", args->threads,
                  "Threads of the step (default 0: the cores available); the results are the "
                  "same for every count")
      ->check(CLI::Range(0, 4096));
  cmd->add_flag("--live", args->live,
                "Serve a live view of the run on 127.0.0.1 (docs/viewer.md): pause, speed, "
                "drag a body with the mouse (its work is external work)");
  cmd->add_option("--live-port", args->livePort,
                  "The live view's port on 127.0.0.1 (default 8765; 0: any free port)")
      ->check(CLI::Range(0, 65535));
  cmd->add_option("--live-wait", args->liveWait,
                  "Wall seconds the live run waits for a first viewer before it starts anyway "
                  "(default 30; 0: no wait)")
      ->type_name("S");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress display");
  cmd->callback([args, &exitCode] { exitCode = runCommand(*args); });
}

}  // namespace robophi::cli
