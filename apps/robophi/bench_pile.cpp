// PILE and SCALING: the contact benchmarks (docs/contact.md).
#include "bench_pile.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "pile_layout.h"
#include "robophi/evaluation.h"
#include "robophi/world.h"

namespace robophi::cli {

namespace {

// Pair stiffness κ_c = 2e4 N/m: the top layer lands at about sqrt(2 g n·5 mm)
// (1.4 m/s for n = 20) on a ball at rest, penetrating v sqrt(m/2 / κ_c) = 0.45 mm
// (< 10% of r = 1 mm); the static load of a 20-ball column, 0.8 N, is 0.04 mm.
constexpr double kPilePairStiffness = 2.0e4;  // N/m
// μ_c for ζ = 0.3 between two balls.
constexpr double kPileDampingRatio = 0.3;
// δ = 1e-4 s: ω = sqrt(κ_c / (m/2)) = 3.1e3 rad/s, ω δ = 0.31; a ball held by
// 12 neighbours has ω δ ≈ 0.76 < 2.
constexpr double kPileStep = 1.0e-4;  // s
// The sticking contacts' tangential damper, as a fraction of critical at the
// contact point (its mass counts the balls' spin: m/7 for two balls). At the
// default, 1, a densely held ball's spin mode is beyond its stability limit at
// δ: the pile at rest makes energy (its account grows by 1.9 J a second on
// PILE-8000, while friction keeps the motion bounded). At 0.5 the account stays
// flat at rest, over 3 s; so it does at 0.6-0.8, and not at 1: half of critical
// keeps a margin below that limit (docs/performance.md, "PILE's tangential damping").
constexpr double kPileTangentialDampingRatio = 0.5;

}  // namespace

Scene makePileScene(int n) {
  Scene scene;
  scene.name = fmt::format("PILE-{}", n * n * n);
  scene.sourcePath = "<bench>";
  Model& model = scene.model;
  model.gravity = {0.0, 0.0, -9.81};
  const double mass = pile::kDensity * 4.0 / 3.0 * M_PI * std::pow(pile::kRadius, 3);
  // Every surface has the same material: pair values are half the material's (series).
  Material material;
  material.name = "pile";
  material.contactStiffness = 2.0 * kPilePairStiffness;
  material.contactDamping =
      2.0 * (2.0 * kPileDampingRatio * std::sqrt(kPilePairStiffness * 0.5 * mass));
  material.staticFriction = pile::kFriction;
  material.kineticFriction = pile::kFriction;
  model.materials.push_back(material);
  model.contact.tangentialDampingRatio = kPileTangentialDampingRatio;
  const std::int32_t pileMaterial = 1;

  const auto count = static_cast<std::size_t>(n) * n * n;
  scene.initial.position.reserve(count);
  model.objects.reserve(count);
  for (const auto& [x, y, z] : pile::centres(n)) {
    const std::int32_t object =
        model.addObject(fmt::format("ball{}", model.objects.size()), "ball", pileMaterial);
    model.addParticle(mass, pile::kRadius, false, object);
    scene.initial.position.push_back(Vec3{x, y, z});
  }
  // Ground and four walls 0.6 m high, 5 cm thick.
  Environment& environment = model.environment;
  environment.planes.push_back(GroundPlane{{0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, pileMaterial});
  for (const pile::Wall& side : pile::walls(n)) {
    BoxObstacle wall;
    wall.material = pileMaterial;
    wall.center = {side.centre[0], side.centre[1], side.centre[2]};
    wall.halfExtents = {side.halfExtents[0], side.halfExtents[1], side.halfExtents[2]};
    environment.boxes.push_back(wall);
  }
  scene.initial.velocity.assign(count, Vec3{});
  scene.run.integrator = Integrator::kSymplecticEuler;
  scene.run.stepMode = StepMode::kConstant;
  scene.run.dt = kPileStep;
  scene.run.duration = 1.0;
  return scene;
}

namespace {

// A loose lattice of `count` balls 2 cm apart, jittered ±2 mm: about half the
// neighbour pairs touch. `oneObject` puts them all in one object (tree search).
Scene makeScalingScene(std::int64_t count, bool oneObject) {
  Scene scene;
  Model& model = scene.model;
  model.gravity = {};
  std::int32_t object = oneObject ? model.addObject("cloud", "particles") : -1;
  model.objects.reserve(oneObject ? 1 : static_cast<std::size_t>(count));
  scene.initial.position.reserve(static_cast<std::size_t>(count));
  for (const auto& [x, y, z] : pile::scalingCentres(count)) {
    if (!oneObject) object = model.addObject("ball", "ball");
    model.addParticle(pile::kScalingMass, pile::kRadius, false, object);
    scene.initial.position.push_back(Vec3{x, y, z});
  }
  scene.initial.velocity.assign(static_cast<std::size_t>(count), Vec3{});
  return scene;
}

}  // namespace

int runContactScaling(bool json) {
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  for (const bool oneObject : {false, true}) {
    const char* mode = oneObject ? "tree" : "grid";
    std::vector<double> logN, logT;
    for (const std::int64_t count : {1000LL, 10000LL, 100000LL, 1000000LL}) {
      Scene scene = makeScalingScene(count, oneObject);
      const CompiledModel model(scene.model);
      // A whole force evaluation (gravity is off and there are no connectors,
      // so it is the contact pass and three O(n) sweeps). The first passes
      // build the sphere trees and grow the buffers; then time.
      Workspace workspace;
      for (int warm = 0; warm < 2; ++warm) evaluate(model, scene.initial, workspace);
      const int repeats = count >= 1000000 ? 2 : (count >= 100000 ? 5 : 20);
      const auto start = std::chrono::steady_clock::now();
      for (int r = 0; r < repeats; ++r) evaluate(model, scene.initial, workspace);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / repeats;
      const ContactStats stats = workspace.result().contactStats;
      const double allPairs = 0.5 * static_cast<double>(count) * static_cast<double>(count - 1);
      logN.push_back(std::log(static_cast<double>(count)));
      logT.push_back(std::log(seconds));
      results.push_back(
          {{"mode", mode},
           {"particles", count},
           {"pass_s", seconds},
           {"contacts", stats.particleContacts},
           {"pair_tests", stats.pairTests},
           {"node_tests", stats.nodeTests},
           {"all_pairs_over_tests", allPairs / static_cast<double>(stats.pairTests)}});
      if (!json) {
        std::printf(
            "SCALING-%s particles=%-8lld pass_s=%-10.4g contacts=%-8lld pair_tests=%-9lld "
            "node_tests=%-9lld all_pairs/tests=%.3g\n",
            mode, static_cast<long long>(count), seconds,
            static_cast<long long>(stats.particleContacts), static_cast<long long>(stats.pairTests),
            static_cast<long long>(stats.nodeTests),
            allPairs / static_cast<double>(stats.pairTests));
        std::fflush(stdout);
      }
    }
    // Least-squares slope of log(time) against log(n).
    double meanN = 0.0, meanT = 0.0;
    for (std::size_t k = 0; k < logN.size(); ++k) {
      meanN += logN[k] / static_cast<double>(logN.size());
      meanT += logT[k] / static_cast<double>(logT.size());
    }
    double covariance = 0.0, variance = 0.0;
    for (std::size_t k = 0; k < logN.size(); ++k) {
      covariance += (logN[k] - meanN) * (logT[k] - meanT);
      variance += (logN[k] - meanN) * (logN[k] - meanN);
    }
    const double slope = covariance / variance;
    results.push_back({{"mode", mode}, {"loglog_slope", slope}});
    if (!json) std::printf("SCALING-%s log-log slope (1e3..1e6) = %.3f\n", mode, slope);
  }
  if (json) std::printf("%s\n", results.dump(2).c_str());
  return 0;
}

// The cost of a whole step per particle from 1e3 to 1e6 particles: the CLOTH
// scene (n × n, LS only) and the SCALING grid scene (single balls, about half
// the neighbour pairs touching, so contacts every step), each stepped with a
// constant step after 16 warm-up steps (trees, lists and buffers built), in
// rounds of 10 steps from the same state (the restores are not timed).
int runStepScaling(bool json, int threads) {
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  struct Family {
    const char* name;
    std::vector<std::int64_t> sizes;
  };
  for (const Family& family : {Family{"cloth", {32, 100, 316, 1000}},
                               Family{"contacts", {1000, 10000, 100000, 1000000}}}) {
    const bool cloth = std::string(family.name) == "cloth";
    double lowest = 0.0, highest = 0.0;
    for (const std::int64_t size : family.sizes) {
      Scene scene = cloth ? makeClothScene(static_cast<int>(size)) : makeScalingScene(size, false);
      const auto particles = static_cast<std::int64_t>(scene.initial.position.size());
      const double dt = cloth ? scene.run.dt : 1.0e-5;
      World world(scene.model, scene.initial, Integrator::kSymplecticEuler);
      world.setThreadCount(threads);
      // Warm-up: the trees, the lists and the buffers are built. The contact
      // lists rotate through three buffers (the history, the evaluation's and
      // the stage's fresh one), and they and the stage's other per-contact
      // buffers grow as the balls' contacts do over the first steps: with two
      // warm-up steps a million balls' new pages (1.4 million contacts, 232
      // bytes each per list) were first touched, and zeroed by the kernel,
      // inside the timed steps (about 40 % of them). The cost per step settles
      // after about 8 steps; 16 leave margin.
      for (int warm = 0; warm < 16; ++warm) world.step(dt);
      // Rounds of 10 steps from the same state (the balls move apart, so a long
      // run would measure a sparser cloud), about 2e7 particle-steps (1e7 with
      // contacts) in all.
      const World::Snapshot start = world.snapshot();
      constexpr std::int64_t kRound = 10;
      const std::int64_t rounds =
          std::max<std::int64_t>(1, (cloth ? 20000000 : 10000000) / (kRound * particles));
      const std::int64_t steps = rounds * kRound;
      bool sound = true;
      double seconds = 0.0;
      for (std::int64_t r = 0; r < rounds && sound; ++r) {
        world.restore(start);
        const auto begin = std::chrono::steady_clock::now();
        for (std::int64_t k = 0; k < kRound && sound; ++k)
          sound = world.step(dt) == StepStatus::kOk;
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      }
      const double perParticleStep = seconds / static_cast<double>(steps * particles);
      lowest = lowest == 0.0 ? perParticleStep : std::min(lowest, perParticleStep);
      highest = std::max(highest, perParticleStep);
      const std::size_t contacts = world.state().frictionHistory.size();
      results.push_back({{"family", family.name},
                         {"particles", particles},
                         {"steps", steps},
                         {"wall_s", seconds},
                         {"s_per_particle_step", perParticleStep},
                         {"contacts", contacts},
                         {"threads", world.threadCount()},
                         {"status", sound ? "ok" : "non-finite"}});
      if (!json) {
        std::printf(
            "STEP-SCALING-%s particles=%-8lld steps=%-6lld wall_s=%-8.3f "
            "ns_per_particle_step=%-7.2f "
            "contacts=%-8zu threads=%d %s\n",
            family.name, static_cast<long long>(particles), static_cast<long long>(steps), seconds,
            1e9 * perParticleStep, contacts, world.threadCount(), sound ? "ok" : "non-finite");
        std::fflush(stdout);
      }
    }
    results.push_back({{"family", family.name}, {"highest_over_lowest", highest / lowest}});
    if (!json)
      std::printf("STEP-SCALING-%s cost per particle-step, highest / lowest (1e3..1e6) = %.3f\n",
                  family.name, highest / lowest);
  }
  if (json) std::printf("%s\n", results.dump(2).c_str());
  return 0;
}

}  // namespace robophi::cli
