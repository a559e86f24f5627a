// robophi run SCENE: simulate and write the results folder (docs/output-format.md).
#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "output/results_folder.h"
#include "robotics/tasks.h"
#include "run/interrupt.h"
#include "run/runner.h"
#include "scene_input.h"

namespace robophi::cli {

namespace {

struct RunArguments {
  std::string scene;
  std::string outDir;
  bool force = false;
  std::optional<double> duration, dt, fps;
  std::string integrator;
  std::string stepMode;
  double energyRate = 1000.0;
  bool quiet = false;
};

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
  auto scene = loadSceneOrReport(args.scene);
  if (!scene) return kExitBadInput;

  RunOptions options;
  options.settings = scene->run;
  if (args.duration) options.settings.duration = *args.duration;
  if (args.dt) options.settings.dt = *args.dt;
  if (args.fps) options.settings.fps = *args.fps;
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
  for (auto [name, value] :
       {std::pair{"--duration", options.settings.duration}, std::pair{"--dt", options.settings.dt},
        std::pair{"--fps", options.settings.fps}, std::pair{"--energy-rate", args.energyRate}}) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      std::fprintf(stderr, "robophi run: %s %g: expected a positive number\n", name, value);
      return kExitBadInput;
    }
  }
  options.energyRate = args.energyRate;
  options.outDir =
      args.outDir.empty()
          ? (std::filesystem::path("out") / std::filesystem::path(args.scene).stem()).string()
          : args.outDir;
  options.force = args.force;
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

  const StabilityEstimate stability = estimateStability(scene->model, &scene->initial.position);
  if (!args.quiet) std::fprintf(stderr, "%s\n", describeScene(*scene, stability).c_str());
  for (const auto& w : preflightWarnings(options.settings, stability)) {
    std::fprintf(stderr, "%s: warning: %s\n", args.scene.c_str(), w.c_str());
  }

  RunReport report;
  try {
    report = runScene(*scene, options);
  } catch (const output::ResultsFolderError& e) {  // the folder changed during the run
    std::fprintf(stderr, "robophi run: --out: %s\n", e.what());
    return kExitBadInput;
  }
  if (!args.quiet && isatty(fileno(stderr))) std::fprintf(stderr, "\n");

  const std::string steps =
      options.settings.stepMode == StepMode::kAdaptive
          ? fmt::format("{} adaptive steps ({} rejected, dt {:.3g} to {:.3g} s)",
                        report.adaptive.accepted, report.adaptive.rejected,
                        report.adaptive.smallestStep, report.adaptive.largestStep)
          : fmt::format("{} constant steps of {:.3g} s", report.steps, options.settings.dt);
  std::printf("%s: %s, %s, %s; %.4g s simulated in %.3f s wall, energy drift %.3g; results in %s\n",
              args.scene.c_str(), report.status.c_str(), steps.c_str(),
              integratorName(options.settings.integrator), report.simulatedTime, report.wallSeconds,
              report.energyDrift, options.outDir.c_str());
  if (report.interrupted()) {
    const int caught = InterruptGuard::caughtSignal();
    std::fprintf(stderr,
                 "%s: interrupted by %s at t = %.6g s: the results so far are in %s "
                 "(summary.json \"status\": \"interrupted\")\n",
                 args.scene.c_str(), caught == SIGTERM ? "SIGTERM" : "SIGINT", report.simulatedTime,
                 options.outDir.c_str());
    return exitCodeForSignal(caught == 0 ? SIGINT : caught);
  }
  if (!report.ok()) {
    std::fprintf(stderr, "%s: error: %s\n", args.scene.c_str(), report.failure.c_str());
    return kExitDiverged;
  }
  return kExitOk;
}

}  // namespace

void addRunCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("run", "Simulate a scene and write its results folder");
  auto args = std::make_shared<RunArguments>();
  cmd->add_option("scene", args->scene, "Scene file (JSON)")->required();
  cmd->add_option("--out", args->outDir,
                  "Results folder (default out/<scene name>); an existing one must hold nothing "
                  "but robophi's results (its robophi-results.json lists them)");
  cmd->add_flag("--force", args->force,
                "Also write into an --out folder that holds other files: they are kept, only "
                "robophi's own files are replaced");
  cmd->add_option("--duration", args->duration, "Model time to simulate (s)");
  cmd->add_option("--step", args->stepMode,
                  "adaptive (energy-based, the default) | constant (use --dt)");
  cmd->add_option("--dt", args->dt, "Constant time step, or the first adaptive trial step (s)");
  cmd->add_option("--integrator", args->integrator, "taylor | symplectic | verlet");
  cmd->add_option("--fps", args->fps, "Frames per model second in particles.csv (default 60)");
  cmd->add_option("--energy-rate", args->energyRate, "Rows of energy.csv per model second");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress display");
  cmd->callback([args, &exitCode] { exitCode = runCommand(*args); });
}

}  // namespace robophi::cli
