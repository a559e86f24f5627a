// robophi bench: the standard scenes, headless, with throughput figures.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bench_pile.h"
#include "bench_scenes.h"
#include "commands.h"
#include "output/results_folder.h"
#include "record.h"
#include "robophi/adaptive_step.h"
#include "robophi/version.h"
#include "run/interrupt.h"
#include "run/runner.h"

namespace robophi::cli {

namespace {

struct BenchArguments {
  bool json = false;
  bool quick = false;
  int threads = 0;        // of the step; 0: the cores available
  double duration = 0.0;  // model seconds of every scene, over its own; 0: its own
  std::string filter;
  std::string record = "bench/results";
};

struct BenchResult {
  std::string name;
  std::int64_t particles = 0, connectors = 0, steps = 0;
  int threads = 1;  // of the step
  double simulatedSeconds = 0.0, wallSeconds = 0.0;
  double particleStepsPerSecond = 0.0, connectorEvalsPerSecond = 0.0;
  std::int64_t rejected = 0;
  // Contact figures: mean contacts per step, deepest penetration (m and / radius).
  double contactsPerStep = 0.0, maxPenetration = 0.0, maxPenetrationFraction = 0.0;
  // Evaluations that rebuilt the grid particles' neighbour list.
  std::int64_t neighbourListBuilds = 0;
  // The energy account: the largest |E_total(t) - E_total(0)| over the energy
  // scale (as `robophi run` keeps it), read at ten points of the run, outside the
  // timed steps. A step beyond a mode's stability limit makes energy: an
  // unstable damper shows here even where friction keeps the motion bounded.
  double accountError = 0.0;
  // The same over the run's second half, |E_total(T) - E_total(T/2)| / scale:
  // where a scene has come to rest (PILE), energy made there is instability.
  double secondHalfAccountChange = 0.0;
  // Constant steps longer than the contacts' own stability estimate at their
  // start (Evaluation::contactCriticalStep, a Gershgorin bound, on the safe side).
  std::int64_t stepsOverContactLimit = 0;
  std::string status;
};

BenchResult runBench(const BenchScene& bench, int threads) {
  const Scene& scene = bench.scene;
  World world(scene.model, scene.initial, scene.run.integrator);
  world.setThreadCount(threads);
  const auto steps = static_cast<std::int64_t>(std::ceil(scene.run.duration / scene.run.dt - 1e-9));
  BenchResult r;
  r.name = bench.name;
  r.threads = world.threadCount();
  r.particles = scene.model.particleCount();
  r.connectors = static_cast<std::int64_t>(scene.model.linearSprings.size() +
                                           scene.model.torsionSprings.size() +
                                           scene.model.jointSprings.size());
  r.status = "ok";
  double contactSum = 0.0;
  // Adaptive: capped at the constant step, so both take the same steps and
  // their wall time per step compares the cost of one iteration.
  AdaptiveStepSettings controller;
  controller.initialStep = controller.maxStep = scene.run.dt;
  AdaptiveStepper stepper(scene.model, controller);
  const double initialTotal = world.energy().total();
  double scale = energyAccountScale(world.model(), world.state(), world.energy());
  double largestError = 0.0, halfwayTotal = initialTotal;
  double untimed = 0.0;  // seconds spent reading the account
  const std::int64_t readEvery = std::max<std::int64_t>(1, steps / 10);
  const auto readAccount = [&](bool firstHalf) {
    const EnergyTally energy = world.energy();
    scale = std::max(scale, energyAccountScale(world.model(), world.state(), energy));
    largestError = std::max(largestError, std::abs(energy.total() - initialTotal));
    if (firstHalf) halfwayTotal = energy.total();
    r.secondHalfAccountChange = std::abs(energy.total() - halfwayTotal);
  };
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t i = 0; i < steps; ++i) {
    if (InterruptGuard::flag().load(std::memory_order_relaxed)) {
      r.status = "interrupted";
      break;
    }
    if (bench.adaptive) {
      const AdaptiveStepResult a = stepper.advance(world, scene.run.duration - world.state().time);
      if (!a.ok) {
        r.status = "stalled";
        break;
      }
      if (world.state().time >= scene.run.duration * (1.0 - 1e-12)) break;
    } else {
      if (scene.run.dt > world.evaluation().contactCriticalStep) ++r.stepsOverContactLimit;
      if (world.step(scene.run.dt) != StepStatus::kOk) {
        r.status = "diverged";
        break;
      }
    }
    if ((i + 1) % readEvery == 0 || i + 1 == steps) {
      const auto before = std::chrono::steady_clock::now();
      readAccount(i + 1 <= steps / 2);
      untimed += std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
    }
    const ContactStats contacts = world.evaluation().contactStats;
    contactSum += static_cast<double>(contacts.particleContacts + contacts.environmentContacts);
    r.neighbourListBuilds += contacts.neighbourListBuilds;
    r.maxPenetration = std::max(r.maxPenetration, contacts.maxPenetration);
    r.maxPenetrationFraction = std::max(r.maxPenetrationFraction, contacts.maxPenetrationFraction);
  }
  r.wallSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - untimed;
  readAccount(false);  // the end state (an adaptive run may end between two readings)
  r.accountError = largestError / scale;
  r.secondHalfAccountChange /= scale;
  if (r.status == "ok" && !(r.accountError <= kDefaultEnergyAccountBound))
    r.status = "energy_account_broken";
  r.contactsPerStep = steps > 0 ? contactSum / static_cast<double>(steps) : 0.0;
  r.steps = world.state().stepCount;
  r.rejected = stepper.stats().rejected;
  r.simulatedSeconds = world.state().time;
  r.particleStepsPerSecond = static_cast<double>(r.particles * r.steps) / r.wallSeconds;
  r.connectorEvalsPerSecond = static_cast<double>(r.connectors * r.steps) / r.wallSeconds;
  return r;
}

nlohmann::ordered_json toJson(const BenchResult& r) {
  return {{"scene", r.name},
          {"status", r.status},
          {"particles", r.particles},
          {"connectors", r.connectors},
          {"threads", r.threads},
          {"steps", r.steps},
          {"simulated_s", r.simulatedSeconds},
          {"wall_s", r.wallSeconds},
          {"particle_steps_per_s", r.particleStepsPerSecond},
          {"connector_evals_per_s", r.connectorEvalsPerSecond},
          {"rejected_steps", r.rejected},
          {"contacts_per_step", r.contactsPerStep},
          {"max_penetration_m", r.maxPenetration},
          {"max_penetration_over_radius", r.maxPenetrationFraction},
          {"neighbour_list_builds", r.neighbourListBuilds},
          {"energy_account_error", r.accountError},
          {"energy_account_change_second_half", r.secondHalfAccountChange},
          {"steps_over_contact_limit", r.stepsOverContactLimit}};
}

int benchCommand(const BenchArguments& args) {
  // STEP-SCALING: a whole step's cost per particle from 1e3 to 1e6 particles.
  if (args.filter.find("STEP-SCALING") != std::string::npos)
    return runStepScaling(args.json, args.threads);
  // SCALING: contact detection cost from 1e3 to 1e6 particles (bench_pile.cpp).
  if (args.filter.find("SCALING") != std::string::npos) return runContactScaling(args.json);
  // RIGID: detection for two rigid objects in contact, 1e3 to 1e5 particles each.
  if (args.filter.find("RIGID") != std::string::npos) return runRigidScaling(args.json);
  // SIGINT, SIGTERM: the scene in progress stops, nothing is recorded.
  InterruptGuard interrupt;
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  for (BenchScene bench : standardBenchScenes(args.quick)) {
    if (!args.filter.empty() && bench.name.find(args.filter) == std::string::npos) continue;
    if (args.duration > 0.0) bench.scene.run.duration = args.duration;
    const BenchResult r = runBench(bench, args.threads);
    if (InterruptGuard::flag()) {
      std::fprintf(stderr, "robophi bench: interrupted: nothing recorded\n");
      return exitCodeForSignal(InterruptGuard::caughtSignal());
    }
    all.push_back(toJson(r));
    if (!args.json) {
      std::printf(
          "%-12s particles=%-7lld connectors=%-7lld steps=%-7lld wall_s=%-8.3f "
          "particle_steps_per_s=%.3e connector_evals_per_s=%.3e threads=%d %s\n",
          r.name.c_str(), static_cast<long long>(r.particles), static_cast<long long>(r.connectors),
          static_cast<long long>(r.steps), r.wallSeconds, r.particleStepsPerSecond,
          r.connectorEvalsPerSecond, r.threads, r.status.c_str());
      std::printf("%-12s energy_account_error=%.2e (of its scale; bound %.2g) "
                  "second_half=%.2e steps_over_contact_limit=%lld\n",
                  r.name.c_str(), r.accountError, kDefaultEnergyAccountBound,
                  r.secondHalfAccountChange, static_cast<long long>(r.stepsOverContactLimit));
      if (r.contactsPerStep > 0.0) {
        std::printf(
            "%-12s contacts_per_step=%.1f max_penetration_m=%.3e (%.1f%% of radius) "
            "neighbour_list_builds=%lld\n",
            r.name.c_str(), r.contactsPerStep, r.maxPenetration, 100.0 * r.maxPenetrationFraction,
            static_cast<long long>(r.neighbourListBuilds));
      }
      std::fflush(stdout);
    }
    if (bench.adaptive) {
      // Wall time per trial step (accepted or rejected) against the constant run's per step.
      for (const auto& other : all) {
        if (other["scene"] != bench.comparedWith) continue;
        const double ats = r.wallSeconds / static_cast<double>(r.steps + r.rejected);
        const double cts = other["wall_s"].get<double>() / other["steps"].get<double>();
        all.back()["ats_over_cts_cost_per_step"] = ats / cts;
        if (!args.json) {
          std::printf("%-12s ATS cost per step / CTS cost per step = %.3f (%lld rejected)\n",
                      r.name.c_str(), ats / cts, static_cast<long long>(r.rejected));
        }
      }
    }
  }
  nlohmann::ordered_json doc = recordHeader();
  doc["quick"] = args.quick;
  doc["results"] = all;
  if (args.json) std::printf("%s\n", doc.dump(2).c_str());
  // A filtered run replaces only its own scenes' results in the record.
  if (!args.record.empty() && !args.quick && args.duration == 0.0) {
    const auto path = std::filesystem::path(args.record) / "latest.json";
    if (!args.filter.empty()) {
      std::ifstream in(path);
      const nlohmann::ordered_json previous = nlohmann::ordered_json::parse(in, nullptr, false);
      if (!previous.is_discarded() && previous.contains("results")) {
        nlohmann::ordered_json merged = nlohmann::ordered_json::array();
        for (const auto& r : previous["results"]) {
          bool replaced = false;
          for (const auto& n : all) replaced = replaced || n["scene"] == r["scene"];
          if (!replaced) merged.push_back(r);
        }
        for (const auto& n : all) merged.push_back(n);
        doc["results"] = merged;
      }
    }
    // Only latest.json under --record, replaced whole or not at all.
    output::writeFileAtomically(path, [&](std::ostream& out) { out << doc.dump(2) << '\n'; });
    if (!args.json) std::printf("recorded in %s\n", path.string().c_str());
  }
  for (const auto& r : all) {
    if (r["status"] != "ok") return kExitDiverged;
  }
  return kExitOk;
}

}  // namespace

void addBenchCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("bench", "Run the standard scenes headless and print throughput");
  auto args = std::make_shared<BenchArguments>();
  cmd->add_flag("--json", args->json, "Print the results as JSON");
  cmd->add_flag("--quick", args->quick, "A short smoke run (not recorded)");
  cmd->add_option("--filter", args->filter, "Only scenes whose name contains this");
  cmd->add_option("--duration", args->duration,
                  "Model seconds of every scene, over its own (a shorter measurement)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--threads", args->threads,
                  "Threads of the step (default 0: the cores available); the results are the "
                  "same for every count")
      ->check(CLI::Range(0, 4096));
  cmd->add_option("--record", args->record,
                  "Folder for latest.json (default bench/results; empty: do not record)");
  cmd->callback([args, &exitCode] { exitCode = benchCommand(*args); });
}

}  // namespace robophi::cli
