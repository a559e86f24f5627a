// Running a scene: steps, the tasks between them, sampling of frames and energy
// rows, progress, interruption, and the staging folder that makes the output
// appear whole or not at all.
#include "run/runner.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include "output/json_numbers.h"
#include "output/replay.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "output/run_writer.h"
#include "robophi/build/input_files.h"
#include "robophi/version.h"
#include "run/checkpoint.h"
#include "run/start_checks.h"

namespace robophi {

std::vector<std::string> preflightWarnings(const RunSettings& settings,
                                           const StabilityEstimate& stability) {
  std::vector<std::string> warnings;
  // Constant steps only: the adaptive step never starts above its stability
  // limit (AdaptiveStepSettings::stabilitySafety × the critical step), so
  // there `dt`, its first trial step, cannot make the run diverge.
  const bool taylor = settings.integrator == Integrator::kTaylor;
  const double critical = criticalStepFor(stability, taylor);
  if (settings.stepMode == StepMode::kConstant && taylor && critical < stability.criticalStep &&
      settings.dt > critical) {
    warnings.push_back(fmt::format(
        "step {:.3g} s exceeds {:.3g} s, the largest step at which the Taylor scheme is stable "
        "(2 gamma/omega_max^2 + 2 tau with the model's least damping: docs/model.md \"The "
        "paper's scheme\"): the run gains energy at every step and may diverge",
        settings.dt, critical));
  } else if (settings.stepMode == StepMode::kConstant && settings.dt > stability.criticalStep) {
    // criticalStep is 2/omega_max reduced for damping (MODEL §2): name it as such.
    warnings.push_back(fmt::format(
        "step {:.3g} s exceeds the critical step {:.3g} s (the stability estimate: 2/omega_max = "
        "{:.3g} s for omega_max = {:.4g} rad/s, reduced for damping; particle {}): the run may "
        "diverge",
        settings.dt, stability.criticalStep, 2.0 / stability.omegaMax, stability.omegaMax,
        stability.limitingParticle));
  }
  return warnings;
}

std::string adaptiveStepLimitProblem(const RunSettings& settings,
                                     const StabilityEstimate& stability) {
  if (settings.stepMode != StepMode::kAdaptive) return {};
  const double ceiling = settings.adaptive.stabilitySafety *
                         criticalStepFor(stability, settings.integrator == Integrator::kTaylor);
  const double fewest = settings.duration / ceiling;
  if (fewest <= kMaxRunSteps) return {};
  return fmt::format(
      "the model's fastest mode (omega_max = {:.3g} rad/s, particle {}) keeps the adaptive step "
      "below {:.3g} s (stabilitySafety x 2/omega_max, reduced for damping): the duration {:g} s "
      "takes at least {:.3g} steps, more than the limit of {:.0e} steps "
      "(docs/scene-format.md#limits); soften the stiffest connectors or make their particles "
      "heavier",
      stability.omegaMax, stability.limitingParticle, ceiling, settings.duration, fewest,
      kMaxRunSteps);
}

std::string driveStepWarning(const RunSettings& settings, const StabilityEstimate& stability,
                             const Evaluation& start) {
  // The joint drives' damping (Evaluation::driveDampingRate) is not in the
  // model's estimate: with their gains set at t = 0, a constant step past the
  // damped limit of both lets the drives make energy (docs/adaptive-step.md).
  if (settings.stepMode != StepMode::kConstant || !(start.driveDampingRate > 0.0)) return {};
  const double limit =
      dampedCriticalStep(stability.omegaMax, stability.dampingRate + start.driveDampingRate);
  if (!(settings.dt > limit)) return {};
  return fmt::format(
      "step {:.3g} s exceeds {:.3g} s, the critical step with the joint drives' damping (a rate "
      "of {:.4g} /s on top of the connectors'): the drives may make energy and the energy "
      "account break",
      settings.dt, limit, start.driveDampingRate);
}

namespace {

// The checkpoint's "scene": its file (absolute), its hash when the run started,
// and for a bare URDF the options it was loaded with (package paths relative to
// the working directory are made absolute: resume may run elsewhere).
nlohmann::json sceneRecord(const Scene& scene, const std::string& hash,
                           const UrdfSceneOptions& urdf) {
  nlohmann::json record = {{"path", std::filesystem::absolute(scene.sourcePath).string()},
                           {"hash", hash}};
  if (isUrdfPath(scene.sourcePath)) {
    std::vector<std::string> paths;
    for (const std::string& p : urdf.packagePaths)
      paths.push_back(std::filesystem::absolute(p).string());
    record["urdf"] = {
        {"package_paths", paths},
        {"fixed_base", urdf.fixedBase ? nlohmann::json(*urdf.fixedBase) : nlohmann::json()},
        {"rigid", urdf.rigid},
        {"particle_size", output::exactNumber(urdf.particleSize)},
        {"particles_per_link", urdf.particlesPerLink}};
  }
  return record;
}

// Energy drift (relative to the account's scale, energyAccountScale: datum- and
// observer-free) above which a finite run is reported as diverged.
constexpr double kRunawayEnergyGrowth = 100.0;

// Kinetic and elastic energy (connectors, contacts): what the energy scale
// follows; gravity's potential is left out, it depends on where z = 0 is.
double activeEnergy(const EnergyTally& e) {
  return e.kinetic + e.linearSpring + e.torsionSpring + e.jointSpring + e.contact;
}

// Where a run went wrong: `particle` (or none), its object, the world's time.
FailurePlace placeOf(const World& world, ParticleIndex particle) {
  FailurePlace at;
  at.time = world.state().time;
  at.step = world.state().stepCount;
  at.particle = particle;
  if (particle != kNoParticle) {
    const auto o = world.model().objectOf[static_cast<std::size_t>(particle)];
    if (o >= 0 && static_cast<std::size_t>(o) < world.model().objects.size())
      at.object = world.model().objects[static_cast<std::size_t>(o)].name;
  }
  return at;
}

std::string describePlace(const FailurePlace& at) {
  if (at.particle == kNoParticle) return fmt::format("t = {:.6g} s, step {}", at.time, at.step);
  return fmt::format("t = {:.6g} s, step {}, particle {}{}", at.time, at.step, at.particle,
                     at.object.empty() ? std::string() : fmt::format(" of object '{}'", at.object));
}

// Ends the run with `status` at `at` (a failure: also one of its warnings).
void fail(RunReport& report, const char* status, const FailurePlace& at, std::string failure) {
  report.status = status;
  report.failurePlace = at;
  report.failure = std::move(failure);
  report.warnings.push_back(report.failure);
}

// The free particle with the most kinetic energy (kNoParticle when none moves).
ParticleIndex mostEnergetic(const World& world) {
  const Model& model = world.model();
  ParticleIndex best = kNoParticle;
  double largest = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (model.isFixed(i)) continue;
    const double e = 0.5 * model.mass[i] * squaredNorm(world.state().velocity[i]);
    if (e > largest || !std::isfinite(e)) {
      largest = e;
      best = i;
      if (!std::isfinite(e)) break;
    }
  }
  return best;
}

// MODEL §3.1's contact is a small overlap of two spheres: a packing of
// spheres touches at most about 12 neighbours per particle (the kissing number,
// a few more for mixed sizes). Far more on average means the particles sit
// inside one another (a heap started in one spot): every step then costs N²
// contacts, the step shrinks to the overlap forces' time scale, and the run
// would take hours for an explosion the model does not describe. Above this
// mean number of touching contacts per particle the run stops (stalled).
constexpr double kMaxMeanContacts = 24.0;

// When the touching contacts overload the particles (kMaxMeanContacts): why,
// and the particle with the most contacts in `blamed`; else empty.
std::string contactOverload(const World& world, ParticleIndex* blamed) {
  const Model& model = world.model();
  const auto n = static_cast<std::size_t>(model.particleCount());
  const std::vector<Contact>& contacts = world.contacts();
  // Each particle pair counts for both particles, an environment contact for one.
  if (n == 0 ||
      2.0 * static_cast<double>(contacts.size()) <= kMaxMeanContacts * static_cast<double>(n))
    return {};
  std::vector<std::int64_t> count(n, 0);
  double touching = 0.0;  // contact ends on particles
  std::int64_t pairs = 0;
  double deepest = 0.0;
  for (const Contact& c : contacts) {
    if (!(c.depth < 0.0)) continue;
    ++pairs;
    ++count[static_cast<std::size_t>(c.a)];
    touching += 1.0;
    double smaller = model.radius[c.a];
    if (!c.withEnvironment()) {
      ++count[static_cast<std::size_t>(c.other)];
      touching += 1.0;
      smaller = std::min(smaller, model.radius[c.other]);
    }
    if (smaller > 0.0) deepest = std::max(deepest, -c.depth / smaller);
  }
  const double mean = touching / static_cast<double>(n);
  if (!(mean > kMaxMeanContacts)) return {};
  const auto most = std::max_element(count.begin(), count.end());
  *blamed = static_cast<ParticleIndex>(most - count.begin());
  return fmt::format(
      "the contacts overload the particles: {} touching contacts among {} particles, {:.1f} "
      "a particle on average (a packing of spheres touches at most about 12 neighbours; the "
      "limit is {:.0f}), particle {} touches {}, the deepest overlap is {:.0f}% of a radius: the "
      "particles sit inside one another, beyond the contact model's small overlaps (MODEL "
      "§3.1), and the step would collapse under their forces; start them apart (within one "
      "object, or turn its self-collision off: contact.selfCollision)",
      pairs, n, mean, kMaxMeanContacts, *blamed, *most, 100.0 * deepest);
}

// The staging folder of a run: a stale one of robophi's (a killed run) is
// cleared first; whatever robophi wrote into it is removed again unless it was
// moved into place (or kept on purpose: a write that failed).
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

// runScene's steps and files: the results go into `staging` (null: none) and
// are published from there to options.outDir.
RunReport runSteps(const Scene& scene, const RunOptions& options, StagingFolder* staging,
                   State* finalState);

}  // namespace

std::string outputFolderProblem(const RunOptions& options) {
  if (options.outDir.empty()) return {};
  std::string problem =
      output::resultsFolderProblem(options.outDir, "run", options.force, runFileNames());
  // The staging folder may be a killed run's (robophi's, cleared) but nothing else.
  if (problem.empty())
    problem =
        output::resultsFolderProblem(output::stagingFolderOf(options.outDir), "run", false, {});
  return problem;
}

RunReport runScene(const Scene& scene, const RunOptions& options, State* finalState) {
  if (options.outDir.empty()) return runSteps(scene, options, nullptr, finalState);
  // One robophi at a time writes a folder; a replacement a kill cut short is
  // finished first (the earlier results put back).
  const output::ResultsFolderLock lock(options.outDir);
  output::recoverResultsFolder(options.outDir);
  if (const std::string problem = outputFolderProblem(options); !problem.empty())
    throw output::ResultsFolderError(problem);
  StagingFolder staging(output::stagingFolderOf(options.outDir).string());
  try {
    return runSteps(scene, options, &staging, finalState);
  } catch (const output::WriteError& e) {
    // A full disk: the earlier results stay; what was written is kept to look at.
    const std::string kept = staging.path();
    staging.release();
    throw output::WriteError(
        fmt::format("{}; the results written so far are kept in {}; {} was left as it was",
                    e.what(), kept, options.outDir));
  }
}

namespace {

RunReport runSteps(const Scene& scene, const RunOptions& options, StagingFolder* staging,
                   State* finalState) {
  using Clock = std::chrono::steady_clock;
  using nlohmann::json;
  const RunSettings& settings = options.settings;
  const json* resume = options.resume;
  RunReport report;
  report.stability = estimateStability(scene.model, &scene.initial.position);
  report.accountBound = options.energyAccountBound;

  // The world: the scene's, or the one a checkpoint saved (its model edits, its
  // state, its tasks' state), evaluated as the step that made it left it.
  Model model = scene.model;
  State initial = scene.initial;
  if (resume) {
    applyModelEdits(resume->at("model_edits"), model);
    initial = stateFromJson(resume->at("state"), model);
  }
  World world(std::move(model), std::move(initial), settings.integrator);
  world.setThreadCount(options.threads);
  // The run's own progress (a checkpoint saves it).
  std::int64_t nextFrame = 0, nextEnergyRow = 0, nextCheckpoint = 1;
  std::int64_t lastFrameStep = -1, lastEnergyStep = -1;
  double largestAccountError = 0.0;  // J
  std::optional<FailurePlace> accountBrokenAt;
  double priorWallSeconds = 0.0;
  if (resume) {
    const json& savedTasks = resume->at("tasks");
    // A live run's checkpoint has its live view last, with no state (null): it
    // resumes without it.
    bool sameTasks = savedTasks.size() >= options.tasks.size();
    for (std::size_t k = options.tasks.size(); sameTasks && k < savedTasks.size(); ++k)
      sameTasks = savedTasks[k].is_null();
    if (!sameTasks)
      throw std::runtime_error("checkpoint: it was written by a run with another set of tasks");
    for (std::size_t k = 0; k < options.tasks.size(); ++k)
      if (options.tasks[k]) options.tasks[k]->restore(savedTasks[k]);
    world.resumeAfterStep(evaluationFromJson(resume->at("evaluation")));
    const json& r = resume->at("run");
    report.warnings = r.at("warnings").get<std::vector<std::string>>();
    report.events = r.at("events").get<std::vector<std::string>>();
    report.initialTotal = output::numberFromJson(r.at("initial_total"), "initial_total");
    report.initialScale = output::numberFromJson(r.at("initial_scale"), "initial_scale");
    report.energyScale = output::numberFromJson(r.at("energy_scale"), "energy_scale");
    largestAccountError = output::numberFromJson(r.at("largest_account_error"), "account error");
    nextFrame = r.at("next_frame").get<std::int64_t>();
    nextEnergyRow = r.at("next_energy_row").get<std::int64_t>();
    nextCheckpoint = r.at("next_checkpoint").get<std::int64_t>();
    lastFrameStep = r.at("last_frame_step").get<std::int64_t>();
    lastEnergyStep = r.at("last_energy_step").get<std::int64_t>();
    report.checkpoints = r.at("checkpoints").get<int>();
    report.lastCheckpointTime = world.state().time;
    priorWallSeconds = output::numberFromJson(r.at("wall_seconds"), "wall_seconds");
    report.resumedFrom = world.state().time;
  } else {
    report.warnings = preflightWarnings(settings, report.stability);
    for (std::string& w : startingOverlapWarnings(scene.model, scene.initial))
      report.warnings.push_back(std::move(w));
    // The tasks' commands at t = 0 (a controller's servos and drives), before the account starts.
    for (const StepTask& task : options.tasks)
      if (task) task->start(world, report.events);
    world.bookExternalWork();
    world.refresh();  // the energy account of the initial state
    if (const std::string w = driveStepWarning(settings, report.stability, world.evaluation());
        !w.empty())
      report.warnings.push_back(w);
    report.initialTotal = world.energy().total();
    // The drift's scale: the energy that can turn into motion in the scene's own
    // frame, or that gravity can release (MODEL §4.1), never E(0), which depends
    // on where z = 0 is.
    report.initialScale =
        std::max(energyAccountScale(world.model(), world.state(), world.energy()), 1e-300);
    report.energyScale = report.initialScale;
  }

  std::optional<RunWriter> writer;
  // The replay page's options: the page written as the run goes and the page
  // ended (or written whole) after it take the same; the page's warnings (a visual
  // mesh not drawn) are the run's.
  std::vector<std::string> replayWarnings;
  ReplayOptions replayOptions;
  replayOptions.warnings = &replayWarnings;
  if (staging) {
    if (resume) {
      // The series so far, copied beside the folder and cut back to the checkpoint.
      const auto sizes = resume->at("files").get<std::map<std::string, std::uintmax_t>>();
      std::filesystem::create_directories(staging->path());
      std::vector<std::string> names;
      for (const auto& [name, size] : sizes) names.push_back(name);
      output::writeResultsMarker(staging->path(), "run", names);
      for (const std::string& name : names) {
        const std::filesystem::path from = std::filesystem::path(options.outDir) / name;
        if (!std::filesystem::exists(from))
          throw std::runtime_error(
              fmt::format("{}: missing; the checkpoint needs it", from.string()));
        std::filesystem::copy_file(from, std::filesystem::path(staging->path()) / name);
      }
      writer.emplace(staging->path(), scene, sizes, options.threads != 1);
    } else {
      writer.emplace(staging->path(), scene, options.writeReplay ? &replayOptions : nullptr,
                     options.threads != 1);
    }
  }
  const std::string sceneHash =
      resume ? resume->at("scene").at("hash").get<std::string>() : fileHash(scene.sourcePath);
  // Every file the run read, as it was when the run started (checkpointProblem
  // compares them on resume); hashed only when a checkpoint may be written.
  const bool checkpoints = options.checkpointEvery > 0.0 || options.stopAfter > 0.0;
  const json inputs = resume        ? resume->value("inputs", json::array())
                      : checkpoints ? inputDigests(scene.inputFiles)
                                    : json::array();

  const auto start = Clock::now();
  auto lastProgress = start;
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
    if (resume) stepper->resume(adaptiveProgressFromJson(resume->at("adaptive")));
  }

  // checkpoint.json: everything the loop below needs to go on from here.
  auto writeCheckpoint = [&]() {
    if (!writer) return;
    const State& state = world.state();
    ++report.checkpoints;
    report.lastCheckpointTime = state.time;
    json tasks = json::array();
    for (const StepTask& task : options.tasks) tasks.push_back(task ? task->save() : json());
    // The series files as far as written, with a digest of their last bytes:
    // the checkpoint goes with this folder's files only.
    const std::map<std::string, std::uintmax_t> sizes = writer->progress();
    json digests = json::object();
    for (const auto& [name, size] : sizes)
      digests[name] = seriesDigest((std::filesystem::path(staging->path()) / name).string(), size);
    json checkpoint = {
        {"robophi", kVersion},
        {"kind", "checkpoint"},
        {"format", 1},
        {"scene", sceneRecord(scene, sceneHash, options.urdf)},
        {"inputs", inputs},
        {"settings", runSettingsToJson(settings)},
        {"energy_rate", output::exactNumber(options.energyRate)},
        {"checkpoint_every", output::exactNumber(options.checkpointEvery)},
        {"energy_account_bound", output::exactNumber(options.energyAccountBound)},
        {"state", stateToJson(state)},
        {"evaluation", evaluationToJson(world.evaluation())},
        {"model_edits", modelEditsToJson(world.model())},
        {"adaptive", stepper ? adaptiveProgressToJson(stepper->progress()) : json()},
        {"run",
         {{"next_frame", nextFrame},
          {"next_energy_row", nextEnergyRow},
          {"next_checkpoint", nextCheckpoint},
          {"last_frame_step", lastFrameStep},
          {"last_energy_step", lastEnergyStep},
          {"initial_total", output::exactNumber(report.initialTotal)},
          {"initial_scale", output::exactNumber(report.initialScale)},
          {"energy_scale", output::exactNumber(report.energyScale)},
          {"largest_account_error", output::exactNumber(largestAccountError)},
          {"checkpoints", report.checkpoints},
          {"wall_seconds",
           priorWallSeconds + std::chrono::duration<double>(Clock::now() - start).count()},
          {"warnings", report.warnings},
          {"events", report.events}}},
        {"files", sizes},
        {"files_digest", digests},
        {"tasks", tasks}};
    writer->writeCheckpoint(checkpoint);
  };

  // Constant steps are counted, not accumulated, so the final time does not drift.
  const auto totalSteps =
      static_cast<std::int64_t>(std::ceil(settings.duration / settings.dt - 1e-9));
  std::int64_t constantSteps = 0, constantSplits = 0;
  // A resumed constant-step run goes on counting its steps of dt.
  if (resume && !adaptive) constantSteps = std::llround(world.state().time / settings.dt);
  if (!resume) sample(adaptive ? stepper->nextStep() : settings.dt, false);
  // A requested stop (a signal) ends the run with its results so far: between
  // steps (with a checkpoint when the run writes them), or inside one, between
  // the substeps of a split constant step or the trials of an adaptive one
  // (`betweenSteps` false: no checkpoint there, as a constant run resumes on k·dt).
  auto interrupted = [&](bool betweenSteps) {
    const State& state = world.state();
    report.status = "interrupted";
    report.warnings.push_back(fmt::format("interrupted at t = {:.6g} s of {:.6g} s, step {}{}",
                                          state.time, settings.duration, state.stepCount,
                                          betweenSteps ? "" : " (within a step)"));
    if (betweenSteps && options.checkpointEvery > 0.0) writeCheckpoint();
  };
  for (;;) {
    const State& state = world.state();
    const bool done =
        adaptive ? state.time >= settings.duration * (1.0 - 1e-12) : constantSteps >= totalSteps;
    if (done) break;
    if (options.stop && options.stop->load(std::memory_order_relaxed)) {
      interrupted(true);
      break;
    }
    // Particles inside one another (a heap in one spot): stop before the step collapses.
    if (ParticleIndex blamed = kNoParticle; true) {
      if (const std::string why = contactOverload(world, &blamed); !why.empty()) {
        const FailurePlace at = placeOf(world, blamed);
        fail(report, "stalled", at, fmt::format("at {}: {}", describePlace(at), why));
        break;
      }
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
      const AdaptiveStepResult r =
          stepper->advance(world, settings.duration - state.time, options.stop);
      if (r.stopped) {
        interrupted(false);
        break;
      }
      if (!r.ok) {
        // The particle the step blames (the largest acceleration), else a non-finite one.
        const FailurePlace at =
            placeOf(world, r.particle != kNoParticle ? r.particle : world.firstNonFiniteParticle());
        fail(report, "stalled", at, fmt::format("at {}: {}", describePlace(at), r.failure));
        break;
      }
      dtUsed = r.dt;
    } else {
      // Bounded work: at most kMaxConstantSubsteps substeps, and a signal stops it between them.
      const StepStatus status = stepWithoutTunnelling(
          world, dtUsed, settings.adaptive.maxPenetrationFraction,
          settings.adaptive.stabilitySafety, &constantSplits, kMaxConstantSubsteps, options.stop);
      if (status == StepStatus::kStopped && options.stop &&
          options.stop->load(std::memory_order_relaxed)) {
        interrupted(false);
        break;
      }
      if (status == StepStatus::kStopped) {  // the state is whole, at a substep's end
        const FailurePlace at = placeOf(world, mostEnergetic(world));
        fail(report, "stalled", at,
             fmt::format("at {}: the constant step {:.3g} s needed at least {} substeps, more than "
                         "the limit of {} (docs/adaptive-step.md): the surfaces approach too fast "
                         "for it or the touching contacts are too stiff (their stability limit now "
                         "{:.3g} s; the connectors' critical step {:.3g} s); that particle moves "
                         "fastest; use a smaller --dt or --step adaptive",
                         describePlace(at), settings.dt, kMaxConstantSubsteps + 1,
                         kMaxConstantSubsteps, world.evaluation().contactCriticalStep,
                         report.stability.criticalStep));
        break;
      }
      if (status != StepStatus::kOk) {
        // The first non-finite particle; when only the energy is, the one with the most.
        const ParticleIndex bad = world.firstNonFiniteParticle();
        const FailurePlace at = placeOf(world, bad != kNoParticle ? bad : mostEnergetic(world));
        fail(report, "diverged", at,
             fmt::format("the state became non-finite at {}{}", describePlace(at),
                         bad == kNoParticle
                             ? std::string(" (the energy: that particle has the most)")
                             : std::string()));
        break;
      }
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
    // The energy account: its scale and its largest error so far.
    const EnergyTally energy = world.energy();
    report.energyScale = std::max(report.energyScale, activeEnergy(energy));
    largestAccountError =
        std::max(largestAccountError, std::abs(energy.total() - report.initialTotal));
    // Where the account first went past its bound (at the scale so far): the
    // place an energy_account_broken verdict names.
    if (!accountBrokenAt && largestAccountError > report.accountBound * report.energyScale)
      accountBrokenAt = placeOf(world, mostEnergetic(world));
    if (stop) break;
    const double t = world.state().time;
    const bool stopHere = options.stopAfter > 0.0 && t >= options.stopAfter * (1.0 - 1e-12) &&
                          t < settings.duration * (1.0 - 1e-12);
    if (options.checkpointEvery > 0.0 &&
        t >= static_cast<double>(nextCheckpoint) * options.checkpointEvery * (1.0 - 1e-12)) {
      nextCheckpoint =
          static_cast<std::int64_t>(std::floor(t / options.checkpointEvery * (1.0 + 1e-12))) + 1;
      if (!stopHere) writeCheckpoint();
    }
    if (stopHere) {
      report.status = "stopped";
      writeCheckpoint();
      report.warnings.push_back(fmt::format(
          "stopped at t = {:.6g} s of {:.6g} s (--stop-after): robophi resume {} continues", t,
          settings.duration, options.outDir));
      break;
    }
    if (options.progress && (world.state().stepCount & 255) == 0) {
      const auto now = Clock::now();
      if (now - lastProgress > std::chrono::milliseconds(100)) {
        lastProgress = now;
        options.progress({world.state().time, settings.duration, world.state().stepCount,
                          std::chrono::duration<double>(now - start).count()});
      }
    }
  }
  if (!report.failed()) sample(adaptive ? stepper->stats().lastStep : settings.dt, true);
  if (stepper) {
    report.adaptive = stepper->stats();
    report.adaptiveFloor = stepper->floor();
  }
  if (constantSplits > 0) {
    report.warnings.push_back(fmt::format(
        "the constant step {:.3g} s was split {} times to keep approaching surfaces from "
        "passing through each other in one step and touching contacts stable (MODEL §4.4): "
        "a smaller --dt avoids it",
        settings.dt, constantSplits));
  }

  const State& last = world.state();
  report.wallSeconds =
      priorWallSeconds + std::chrono::duration<double>(Clock::now() - start).count();
  report.steps = last.stepCount;
  report.simulatedTime = last.time;
  const EnergyTally finalEnergy = world.energy();
  report.finalTotal = finalEnergy.total();
  report.dissipated = finalEnergy.dissipated;
  report.implicitLoss = finalEnergy.implicitLoss;
  report.externalWork = finalEnergy.external;
  report.energyDrift = (report.finalTotal - report.initialTotal) / report.energyScale;
  report.largestAccountError = largestAccountError / report.energyScale;
  // Runaway energy is numerical trouble even while every number stays finite.
  // Its scale is what the run had to spend: the initial scale, or the work done
  // on it from outside (drives, servos, edits) when that is larger. A scene that
  // starts at rest, out of contact and without gravity has an initial scale of
  // zero, and its account moves by the round-off of the driven work.
  const double runawayScale = std::max(report.initialScale, std::abs(report.externalWork));
  const double growth = (report.finalTotal - report.initialTotal) / runawayScale;
  if (report.ok() && growth > kRunawayEnergyGrowth) {
    const FailurePlace at = placeOf(world, mostEnergetic(world));
    // The Taylor scheme on undamped stiffness has no stable step at all.
    const std::string cause =
        settings.integrator == Integrator::kTaylor && report.stability.taylorStep == 0.0
            ? "the paper's Taylor scheme gains energy at any step on undamped stiffness (its "
              "step matrix has determinant 1 + (omega delta)^2/2; docs/model.md \"The paper's "
              "scheme\"): give the connectors or the particles damping (then it is stable "
              "below 2 gamma/omega^2 + 2 c/k) or use --integrator verlet"
            : fmt::format(
                  "the step is too large for the model's stiffness (estimate "
                  "2/omega_max = {:.3g} s)",
                  report.stability.criticalStep);
    fail(report, "diverged", at,
         fmt::format("the energy grew to {:.3g} times its scale {:.3g} J (the initial scale or "
                     "the work from outside, whichever is larger; E + dissipated - external, "
                     "from {:.6g} J to {:.6g} J; fastest at the end: {}): {}",
                     growth, runawayScale, report.initialTotal, report.finalTotal,
                     describePlace(at), cause));
  }
  // The tasks' outcomes as data; a goal not reached by the end is a status.
  for (const StepTask& task : options.tasks) {
    if (!task) continue;
    const json outcome = task->outcomes(world);
    if (outcome.is_object()) report.outcomes.update(outcome);
  }
  if (report.outcomes.contains("goals")) {
    for (const json& goal : report.outcomes["goals"])
      if (!goal.value("reached", true)) report.goalsNotReached.push_back(goal.value("name", ""));
  }
  if (report.ok() && report.largestAccountError > report.accountBound) {
    // Where it first went past the bound, with the most energetic particle then
    // (else, after a resume, the end and its most energetic particle).
    const FailurePlace at =
        accountBrokenAt ? *accountBrokenAt : placeOf(world, mostEnergetic(world));
    fail(report, "energy_account_broken", at,
         fmt::format("the energy account (E + dissipated - external) drifted by up to {:.3g} of "
                     "its scale {:.3g} J (bound {:.3g}; final drift {:.3g}), first past the "
                     "bound at {}: the integration is not to be trusted; try a smaller --dt or "
                     "--tolerance",
                     report.largestAccountError, report.energyScale, report.accountBound,
                     report.energyDrift, describePlace(at)));
  }
  if (report.ok() && !report.goalsNotReached.empty()) {
    report.status = "goal_not_reached";
    std::string names;
    for (const std::string& name : report.goalsNotReached)
      names += (names.empty() ? "'" : ", '") + name + "'";
    report.failure = fmt::format("goal {} not reached by t = {:.6g} s (summary.json \"outcomes\")",
                                 names, report.simulatedTime);
    report.warnings.push_back(report.failure);
  }
  report.stateHash = stateHash(last);
  if (finalState) *finalState = last;

  if (writer) {
    // Every run that wrote results gets its page, an interrupted or failed one too:
    // the page of the rows it kept is ended (0.05 s where the rows are kept). A
    // stopped run (--stop-after) is to be resumed: its page comes at its end.
    const bool stopped = report.status == "stopped";
    if (options.writeReplay && stopped) {
      report.warnings.push_back(
          fmt::format("replay.html not written ({}): robophi export html {} makes it",
                      report.status, options.outDir));
    }
    writer->finish(scene, settings, report);
    const std::optional<ReplayRows> rows = writer->takeReplayRows();
    std::unique_ptr<ReplayPageStream> page = writer->takeReplayPage();
    writer.reset();
    // The replay page is built from the rows the run kept (else, after a resume
    // or a number that is not finite, from the finished files); a failure there
    // is a warning (the results are complete without it).
    std::string replayError;
    if (options.writeReplay && !stopped &&
        !(rows ? writeReplayHtml(staging->path(), replayOptions, *rows, page.get(), replayError)
               : writeReplayHtml(staging->path(), replayOptions, replayError))) {
      report.warnings.push_back("replay.html not written: " + replayError);
    }
    report.warnings.insert(report.warnings.end(), replayWarnings.begin(), replayWarnings.end());
    page.reset();  // (a page not ended is removed)
    output::removeFromResultsMarker(staging->path(), kReplayPagePartial);
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

}  // namespace

nlohmann::json readCheckpoint(const std::string& dir) {
  const std::filesystem::path path = std::filesystem::path(dir) / "checkpoint.json";
  std::string text;
  try {
    text = build::readInputFile(path.string());  // a regular file, never a FIFO
  } catch (const build::InputFileError& e) {
    throw std::runtime_error(fmt::format(
        "{}: no checkpoint ({}; run with --checkpoint-every S or --stop-after S to write one)",
        path.string(), e.problem()));
  }
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || j.value("kind", "") != "checkpoint" ||
      j.value("format", 0) != 1) {
    throw std::runtime_error(fmt::format("{}: not a robophi checkpoint (format 1)", path.string()));
  }
  return j;
}

CheckpointedRun checkpointedRun(const nlohmann::json& checkpoint) {
  CheckpointedRun run;
  const nlohmann::json& scene = checkpoint.at("scene");
  run.scenePath = scene.at("path").get<std::string>();
  run.sceneHash = scene.at("hash").get<std::string>();
  if (scene.contains("urdf")) {
    const nlohmann::json& urdf = scene.at("urdf");
    run.urdf.packagePaths = urdf.at("package_paths").get<std::vector<std::string>>();
    if (!urdf.at("fixed_base").is_null()) run.urdf.fixedBase = urdf.at("fixed_base").get<bool>();
    // Checkpoints written before the rigid default were of the particle model.
    run.urdf.rigid = urdf.contains("rigid") && urdf.at("rigid").get<bool>();
    run.urdf.particleSize = output::numberFromJson(urdf.at("particle_size"), "particle_size");
    run.urdf.particlesPerLink = urdf.at("particles_per_link").get<int>();
  }
  run.settings = runSettingsFromJson(checkpoint.at("settings"));
  run.energyRate = output::numberFromJson(checkpoint.at("energy_rate"), "energy_rate");
  run.checkpointEvery =
      output::numberFromJson(checkpoint.at("checkpoint_every"), "checkpoint_every");
  run.energyAccountBound =
      output::numberFromJson(checkpoint.at("energy_account_bound"), "energy_account_bound");
  run.time = output::numberFromJson(checkpoint.at("state").at("time"), "time");
  return run;
}

}  // namespace robophi
