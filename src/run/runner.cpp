// Running a scene: steps, the tasks between them, sampling of frames and energy
// rows, progress, interruption, and the staging folder that makes the output
// appear whole or not at all.
#include "run/runner.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "output/replay.h"
#include "output/results_folder.h"
#include "output/run_writer.h"

namespace robophi {

std::vector<std::string> preflightWarnings(const RunSettings& settings,
                                           const StabilityEstimate& stability) {
  std::vector<std::string> warnings;
  if (settings.dt > stability.criticalStep) {
    warnings.push_back(fmt::format(
        "step {:.3g} s exceeds the stability estimate 2/omega_max = {:.3g} s (set by particle "
        "{}): the run may diverge",
        settings.dt, stability.criticalStep, stability.limitingParticle));
  }
  return warnings;
}

namespace {

// Energy drift (relative to the account's scale, energyAccountScale: datum- and
// observer-free) above which a finite run is reported as diverged.
constexpr double kRunawayEnergyGrowth = 100.0;

// A folder beside `target` that is renamed to it when complete.
std::string stagingFolder(const std::string& target) {
  std::filesystem::path path(target);
  if (path.filename().empty()) path = path.parent_path();
  return (path.parent_path() / ("." + path.filename().string() + ".partial")).string();
}

// The staging folder of a run: a stale one of robophi's (a killed run) is
// cleared first; whatever robophi wrote into it is removed again unless it was
// moved into place (or kept on purpose).
class StagingFolder {
 public:
  explicit StagingFolder(std::string path) : path_(std::move(path)) {
    output::removeOwnedEntries(path_, /*removeFolder=*/true);
  }
  ~StagingFolder() {
    if (path_.empty()) return;
    try {
      output::removeOwnedEntries(path_, /*removeFolder=*/true);
    } catch (const std::exception&) {  // already unwinding or failing: leave it
    }
  }
  StagingFolder(const StagingFolder&) = delete;
  StagingFolder& operator=(const StagingFolder&) = delete;
  const std::string& path() const { return path_; }
  /// Nothing to clean up any more.
  void release() { path_.clear(); }

 private:
  std::string path_;
};

// Time of the sample `index` of a series sampled `rate` times per second.
double sampleTime(std::int64_t index, double rate) { return static_cast<double>(index) / rate; }

}  // namespace

std::string outputFolderProblem(const RunOptions& options) {
  if (options.outDir.empty()) return {};
  std::string problem =
      output::resultsFolderProblem(options.outDir, "run", options.force, runFileNames());
  // The staging folder may be a killed run's (robophi's, cleared) but nothing else.
  if (problem.empty())
    problem = output::resultsFolderProblem(stagingFolder(options.outDir), "run", false, {});
  return problem;
}

RunReport runScene(const Scene& scene, const RunOptions& options, State* finalState) {
  using Clock = std::chrono::steady_clock;
  const RunSettings& settings = options.settings;
  RunReport report;
  report.stability = estimateStability(scene.model, &scene.initial.position);
  report.warnings = preflightWarnings(settings, report.stability);

  World world(scene.model, scene.initial, settings.integrator);
  world.refresh();  // the energy account of the initial state
  report.initialTotal = world.energy().total();
  // The drift's scale: the energy that can turn into motion in the scene's own
  // frame, or that gravity can release (MODEL §4.1), never E(0), which depends
  // on where z = 0 is.
  const double energyScale = energyAccountScale(world.model(), world.state(), world.energy());

  std::optional<StagingFolder> staging;
  std::optional<RunWriter> writer;
  if (!options.outDir.empty()) {
    if (const std::string problem = outputFolderProblem(options); !problem.empty())
      throw output::ResultsFolderError(problem);
    staging.emplace(stagingFolder(options.outDir));
    writer.emplace(staging->path(), scene);
  }

  const auto start = Clock::now();
  auto lastProgress = start;
  std::int64_t nextFrame = 0, nextEnergyRow = 0;
  std::int64_t lastFrameStep = -1, lastEnergyStep = -1;
  // Writes the frame and energy row due at the state's time (the first state
  // at or after each sample time; `last` forces both unless already written).
  auto sample = [&](double dtUsed, bool last) {
    if (!writer) return;
    const State& state = world.state();
    const double slack = 1e-9 * settings.dt;
    if ((last && lastFrameStep != state.stepCount) ||
        state.time >= sampleTime(nextFrame, settings.fps) - slack) {
      writer->writeFrame(world);
      lastFrameStep = state.stepCount;
      nextFrame = static_cast<std::int64_t>(std::floor(state.time * settings.fps + 1e-6)) + 1;
    }
    if ((last && lastEnergyStep != state.stepCount) ||
        state.time >= sampleTime(nextEnergyRow, options.energyRate) - slack) {
      lastEnergyStep = state.stepCount;
      writer->writeEnergyRow(world, dtUsed);
      nextEnergyRow =
          static_cast<std::int64_t>(std::floor(state.time * options.energyRate + 1e-6)) + 1;
    }
  };

  const bool adaptive = settings.stepMode == StepMode::kAdaptive;
  std::optional<AdaptiveStepper> stepper;
  if (adaptive) {
    AdaptiveStepSettings controller = settings.adaptive;
    controller.initialStep = settings.dt;  // RunSettings::dt is the first trial step
    stepper.emplace(world.model(), controller);
  }
  // Constant steps are counted, not accumulated, so the final time does not drift.
  const auto totalSteps =
      static_cast<std::int64_t>(std::ceil(settings.duration / settings.dt - 1e-9));
  std::int64_t constantSteps = 0, constantSplits = 0;
  sample(adaptive ? stepper->nextStep() : settings.dt, false);
  for (;;) {
    const State& state = world.state();
    const bool done =
        adaptive ? state.time >= settings.duration * (1.0 - 1e-12) : constantSteps >= totalSteps;
    if (done) break;
    // A requested stop (a signal) ends the run between steps, with its results so far.
    if (options.stop && options.stop->load(std::memory_order_relaxed)) {
      report.status = "interrupted";
      report.warnings.push_back(fmt::format("interrupted at t = {:.6g} s of {:.6g} s, step {}",
                                            state.time, settings.duration, state.stepCount));
      break;
    }
    double dtUsed = settings.dt;
    // A constant step lands on k·dt exactly (the last one clipped to the
    // duration), so the end time is the duration and end-of-run tasks fire.
    if (!adaptive) {
      const double target =
          std::min(static_cast<double>(++constantSteps) * settings.dt, settings.duration);
      dtUsed = target - state.time;
    }
    if (adaptive) {
      const AdaptiveStepResult r = stepper->advance(world, settings.duration - state.time);
      if (!r.ok) {
        report.status = "stalled";
        report.failure = r.failure;
        report.warnings.push_back(r.failure);
        break;
      }
      dtUsed = r.dt;
    } else if (stepWithoutTunnelling(world, dtUsed, settings.adaptive.maxPenetrationFraction,
                                     settings.adaptive.stabilitySafety,
                                     &constantSplits) != StepStatus::kOk) {
      report.status = "diverged";
      const ParticleIndex bad = world.firstNonFiniteParticle();
      report.failure = fmt::format(
          "the state became non-finite at t = {:.6g} s, step {}{}", world.state().time,
          world.state().stepCount,
          bad == kNoParticle ? std::string(" (energy)") : fmt::format(", particle {}", bad));
      report.warnings.push_back(report.failure);
      break;
    }
    sample(dtUsed, false);
    // Tasks between steps (docs/robotics.md), in order; the first to say so ends the run.
    bool stop = false;
    for (const StepTask& task : options.tasks) {
      if (task && !task(world, report.events)) {
        stop = true;
        break;
      }
    }
    world.bookExternalWork();  // what the tasks changed is work from outside
    if (stop) break;
    if (options.progress && (world.state().stepCount & 255) == 0) {
      const auto now = Clock::now();
      if (now - lastProgress > std::chrono::milliseconds(100)) {
        lastProgress = now;
        options.progress({world.state().time, settings.duration, world.state().stepCount,
                          std::chrono::duration<double>(now - start).count()});
      }
    }
  }
  if (report.ok() || report.interrupted())
    sample(adaptive ? stepper->stats().lastStep : settings.dt, true);
  if (stepper) report.adaptive = stepper->stats();
  if (constantSplits > 0) {
    report.warnings.push_back(fmt::format(
        "the constant step {:.3g} s was split {} times to keep approaching surfaces from "
        "passing through each other in one step and touching contacts stable (MODEL §4.4): "
        "a smaller --dt avoids it",
        settings.dt, constantSplits));
  }

  const State& last = world.state();
  report.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  report.steps = last.stepCount;
  report.simulatedTime = last.time;
  const EnergyTally finalEnergy = world.energy();
  report.finalTotal = finalEnergy.total();
  report.dissipated = finalEnergy.dissipated;
  report.externalWork = finalEnergy.external;
  report.energyDrift = (report.finalTotal - report.initialTotal) / energyScale;
  // Runaway energy is numerical trouble even while every number stays finite.
  if (report.ok() && report.energyDrift > kRunawayEnergyGrowth) {
    report.status = "diverged";
    report.failure = fmt::format(
        "the energy grew to {:.3g} times its initial value (E + dissipated, from {:.6g} J to "
        "{:.6g} J): the step is too large for the model's stiffness (estimate 2/omega_max = "
        "{:.3g} s)",
        report.energyDrift, report.initialTotal, report.finalTotal, report.stability.criticalStep);
    report.warnings.push_back(report.failure);
  }
  report.stateHash = stateHash(last);
  if (finalState) *finalState = last;

  if (writer) {
    // An interrupted run stops quickly: its page can be made later.
    if (options.writeReplay && report.interrupted()) {
      report.warnings.push_back(
          fmt::format("replay.html not written (interrupted): robophi export html {} makes it",
                      options.outDir));
    }
    writer->finish(scene, settings, report);
    writer.reset();
    // The replay page is built from the finished files; a failure there is a
    // warning (the results are complete without it).
    std::string replayError;
    if (options.writeReplay && !report.interrupted() &&
        !writeReplayHtml(staging->path(), ReplayOptions{}, replayError)) {
      report.warnings.push_back("replay.html not written: " + replayError);
    }
    try {
      output::publishResultsFolder(staging->path(), options.outDir, "run", options.force);
    } catch (const output::ResultsFolderError&) {
      staging->release();  // the folder changed during the run: keep the results where they are
      throw;
    }
    staging->release();
  }
  return report;
}

}  // namespace robophi
