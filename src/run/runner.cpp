// Running a scene: steps, sampling of frames and energy rows, progress, and the
// staging folder that makes the output appear whole or not at all.
#include "robophi/runner.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "integrate/integrators.h"
#include "io/run_writer.h"

namespace robophi {

std::vector<std::string> preflightWarnings(const Scene& scene, const RunSettings& settings,
                                           const StabilityEstimate& stability) {
  (void)scene;
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

// A folder beside `target` that is renamed to it when complete.
std::string stagingFolder(const std::string& target) {
  std::filesystem::path path(target);
  if (path.filename().empty()) path = path.parent_path();
  return (path.parent_path() / ("." + path.filename().string() + ".partial")).string();
}

// Time of the sample `index` of a series sampled `rate` times per second.
double sampleTime(std::int64_t index, double rate) { return static_cast<double>(index) / rate; }

}  // namespace

RunReport runScene(const Scene& scene, const RunOptions& options, State* finalState) {
  using Clock = std::chrono::steady_clock;
  const RunSettings& settings = options.settings;
  RunReport report;
  report.stability = estimateStability(scene.model);
  report.warnings = preflightWarnings(scene, settings, report.stability);

  World world(scene.model, scene.initial, settings.integrator);
  {
    // The energy account of the initial state.
    State& initial = world.mutableState();
    computeForces(world.model(), initial);
    initial.energy.kinetic = kineticEnergy(world.model(), initial);
  }
  report.initialTotal = world.state().energy.total();
  const double energyScale = std::max(std::abs(world.state().energy.mechanical()), 1e-12);

  std::optional<RunWriter> writer;
  std::string staging;
  if (!options.outDir.empty()) {
    staging = stagingFolder(options.outDir);
    std::filesystem::remove_all(staging);
    writer.emplace(staging, scene);
  }

  const auto start = Clock::now();
  auto lastProgress = start;
  std::int64_t nextFrame = 0, nextEnergyRow = 0;
  const double dt = settings.dt;
  // Steps are counted, not accumulated, so the final time does not drift.
  const auto totalSteps = static_cast<std::int64_t>(std::ceil(settings.duration / dt - 1e-9));
  for (std::int64_t step = 0; step <= totalSteps; ++step) {
    const State& state = world.state();
    if (writer) {
      // Sample at the first step at or after each frame / energy-row time.
      if (state.time >= sampleTime(nextFrame, settings.fps) - 0.5 * dt || step == totalSteps) {
        writer->writeFrame(world.model(), state);
        nextFrame = static_cast<std::int64_t>(std::floor(state.time * settings.fps + 0.5)) + 1;
      }
      if (state.time >= sampleTime(nextEnergyRow, options.energyRate) - 0.5 * dt ||
          step == totalSteps) {
        writer->writeEnergyRow(state, dt);
        nextEnergyRow =
            static_cast<std::int64_t>(std::floor(state.time * options.energyRate + 0.5)) + 1;
      }
    }
    if (step == totalSteps) break;
    if (world.step(dt) != StepStatus::kOk) {
      report.status = "diverged";
      const ParticleIndex bad = world.firstNonFiniteParticle();
      report.failure = fmt::format(
          "the state became non-finite at t = {:.6g} s, step {}{}", world.state().time,
          world.state().stepCount,
          bad == kNoParticle ? std::string(" (energy)") : fmt::format(", particle {}", bad));
      report.warnings.push_back(report.failure);
      break;
    }
    if (options.progress && (step & 255) == 0) {
      const auto now = Clock::now();
      if (now - lastProgress > std::chrono::milliseconds(100)) {
        lastProgress = now;
        options.progress({world.state().time, settings.duration, world.state().stepCount,
                          std::chrono::duration<double>(now - start).count()});
      }
    }
  }

  const State& last = world.state();
  report.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
  report.steps = last.stepCount;
  report.simulatedTime = last.time;
  report.finalTotal = last.energy.total();
  report.dissipated = last.energy.dissipated;
  report.energyDrift = (report.finalTotal - report.initialTotal) / energyScale;
  report.stateHash = stateHash(last);
  if (finalState) *finalState = last;

  if (writer) {
    writer->finish(scene, settings, report);
    writer.reset();
    std::filesystem::remove_all(options.outDir);
    std::filesystem::rename(staging, options.outDir);
  }
  return report;
}

}  // namespace robophi
