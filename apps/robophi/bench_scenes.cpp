#include "bench_scenes.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_pile.h"
#include "robophi/build/objects.h"
#include "robophi/evaluation.h"
#include "robophi/rotation.h"

namespace robophi::cli {

Scene makeClothScene(int n) {
  constexpr double kSpacing = 0.01;     // m
  constexpr double kTotalMass = 1.0;    // kg
  constexpr double kStiffness = 1.0e4;  // N/m
  Scene scene;
  scene.name = fmt::format("CLOTH-{}", n);
  scene.sourcePath = "<bench>";
  Model& model = scene.model;
  model.gravity = {0.0, 0.0, -9.81};
  // The CLOTH figure measures connectors and integration, as the other engines'
  // cloth figures do: no contact (self-collision would double its cost).
  model.contact.enabled = false;
  const double particleMass = kTotalMass / (n * n);
  const int object = model.addObject("cloth", "plate");
  auto index = [n](int i, int j) { return static_cast<ParticleIndex>(j * n + i); };
  scene.initial.position.reserve(static_cast<std::size_t>(n * n));
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const bool fixed = j == 0 && (i == 0 || i == n - 1);
      model.addParticle(particleMass, 0.5 * kSpacing, fixed, object);
      scene.initial.position.push_back({i * kSpacing, j * kSpacing, 0.0});
    }
  }
  const double damping = 0.2 * std::sqrt(kStiffness * particleMass);
  auto spring = [&](ParticleIndex a, ParticleIndex b, double rest) {
    model.linearSprings.push_back({a, b, rest, kStiffness, damping});
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) spring(index(i, j), index(i + 1, j), kSpacing);
      if (j + 1 < n) spring(index(i, j), index(i, j + 1), kSpacing);
      if (i + 1 < n && j + 1 < n) {
        spring(index(i, j), index(i + 1, j + 1), std::sqrt(2.0) * kSpacing);
        spring(index(i + 1, j), index(i, j + 1), std::sqrt(2.0) * kSpacing);
      }
    }
  }
  scene.initial.velocity.assign(scene.initial.position.size(), Vec3{});
  scene.run.integrator = Integrator::kSymplecticEuler;
  scene.run.dt = 1.0e-4 * 32.0 / n;
  scene.run.duration = 1.0;
  return scene;
}

std::vector<BenchScene> standardBenchScenes(bool quick) {
  std::vector<BenchScene> scenes;
  for (int n : {32, 64, 128}) {
    Scene cloth = makeClothScene(n);
    if (quick) cloth.run.duration = 0.01;
    scenes.push_back({cloth.name, std::move(cloth), false, ""});
  }
  for (int n : {10, 20}) {
    Scene pile = makePileScene(n);
    if (quick) pile.run.duration = 0.01;
    scenes.push_back({pile.name, std::move(pile), false, ""});
  }
  // PILE-8000 in the paper's contact model (friction at the particle centres,
  // no spin): the workload the contact code had before rolling (issue 11).
  {
    Scene pile = makePileScene(20);
    pile.name = "PILE-NOROLL-8000";
    pile.model.contact.rolling = false;
    if (quick) pile.run.duration = 0.01;
    scenes.push_back({pile.name, std::move(pile), false, ""});
  }
  // The cost of one ATS step against one CTS step on the same steps (issue 4).
  for (const std::string& base : {std::string("CLOTH-64"), std::string("PILE-1000")}) {
    for (const BenchScene& b : scenes) {
      if (b.name != base) continue;
      BenchScene adaptive{base + "-ATS", b.scene, true, base};
      if (!quick) adaptive.scene.run.duration = std::min(adaptive.scene.run.duration, 0.5);
      scenes.push_back(std::move(adaptive));
      break;
    }
  }
  return scenes;
}

Scene makeRigidPairScene(int cellsPerSide, bool rigid) {
  constexpr double kCell = 0.01;  // m
  Scene scene;
  scene.name = fmt::format("RIGID-{}", cellsPerSide);
  Model& model = scene.model;
  model.gravity = {};
  const double side = kCell * cellsPerSide;
  for (int body = 0; body < 2; ++body) {
    // The cube's lattice only (its connectors, which BoxSpec would make and the
    // model budget would count, play no part in the detection measured here): a
    // particle of diameter kCell and 1 g at each cell's centre.
    const Vec3 center{body * (side - 0.2 * kCell), 0.0, 0.0};
    build::GeneratedObject box;
    for (int i = 0; i < cellsPerSide; ++i)
      for (int j = 0; j < cellsPerSide; ++j)
        for (int k = 0; k < cellsPerSide; ++k) {
          box.position.push_back(center + Vec3{(i + 0.5) * kCell, (j + 0.5) * kCell, (k + 0.5) * kCell} -
                                 Vec3{0.5 * side, 0.5 * side, 0.5 * side});
          box.mass.push_back(1e-3);
          box.radius.push_back(0.5 * kCell);
        }
    if (body == 1) build::rotateObject(box, center, {1.0, 0.0, 0.0}, 10.0 * M_PI / 180.0);
    const std::int32_t object = model.addObject(body == 0 ? "a" : "b", "box");
    model.objects[static_cast<std::size_t>(object)].rigid = rigid;
    for (std::size_t i = 0; i < box.size(); ++i) {
      model.addParticle(box.mass[i], box.radius[i], false, object);
      scene.initial.position.push_back(box.position[i]);
    }
  }
  model.contact.selfCollision = false;
  // The hierarchy search at every evaluation, as the paper's C(n) counts it (no
  // pair list kept between evaluations: ContactSettings::neighbourSkin 0).
  model.contact.neighbourSkin = 0.0;
  scene.initial.velocity.assign(scene.initial.position.size(), Vec3{});
  return scene;
}

namespace {

// Least-squares slope of y against x.
double slopeOf(const std::vector<double>& x, const std::vector<double>& y) {
  double meanX = 0.0, meanY = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    meanX += x[k] / static_cast<double>(x.size());
    meanY += y[k] / static_cast<double>(y.size());
  }
  double covariance = 0.0, variance = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    covariance += (x[k] - meanX) * (y[k] - meanY);
    variance += (x[k] - meanX) * (x[k] - meanX);
  }
  return covariance / variance;
}

// The RIGID pair `repeats` times over, the second cube moved rigidly a little more
// each time: sliding along +y at 0.2 m/s and turning at 1 rad/s about x through its
// centre, at 1e-4 s intervals (the states are made before the timing starts).
std::vector<State> movingStates(const Scene& scene, int repeats) {
  const std::vector<Vec3>& start = scene.initial.position;
  const std::size_t half = start.size() / 2;
  Vec3 center;
  for (std::size_t i = half; i < start.size(); ++i) center += start[i] / static_cast<double>(half);
  std::vector<State> states(static_cast<std::size_t>(repeats), scene.initial);
  for (int r = 0; r < repeats; ++r) {
    const double t = 1e-4 * (r + 1);
    const Mat3 turn = rotationAboutAxis({1.0, 0.0, 0.0}, 1.0 * t);
    for (std::size_t i = half; i < start.size(); ++i)
      states[static_cast<std::size_t>(r)].position[i] =
          center + Vec3{0.0, 0.2 * t, 0.0} + turn * (start[i] - center);
  }
  return states;
}

}  // namespace

int runRigidScaling(bool json) {
  nlohmann::ordered_json results = nlohmann::ordered_json::array();
  // rigid and refit: one evaluation at the start, again and again; moving: one
  // evaluation a state while the second cube slides and turns on the first
  // (movingStates: its tree moved with its frame, the contacts changing).
  for (const char* mode : {"rigid", "refit", "moving"}) {
    const bool rigid = std::string(mode) != "refit", moving = std::string(mode) == "moving";
    std::vector<double> logN, logTests, logTime;
    for (const int cells : {10, 14, 22, 32, 46}) {
      const Scene scene = makeRigidPairScene(cells, rigid);
      const CompiledModel model(scene.model);
      Workspace workspace;
      for (int warm = 0; warm < 2; ++warm) evaluate(model, scene.initial, workspace);
      const std::int64_t n = static_cast<std::int64_t>(cells) * cells * cells;
      // Processor time, not wall time: steadier on a shared machine.
      const int repeats = n >= 30000 ? 10 : 100;
      const std::vector<State> states = moving ? movingStates(scene, repeats) : std::vector<State>{};
      const std::clock_t start = std::clock();
      for (int r = 0; r < repeats; ++r)
        evaluate(model, moving ? states[static_cast<std::size_t>(r)] : scene.initial, workspace);
      const double seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / repeats;
      const ContactStats stats = workspace.result().contactStats;
      const double tests = static_cast<double>(stats.nodeTests + stats.pairTests);
      logN.push_back(std::log(static_cast<double>(n)));
      logTests.push_back(std::log(tests));
      logTime.push_back(std::log(seconds));
      results.push_back({{"mode", mode},
                         {"particles_per_object", n},
                         {"node_tests", stats.nodeTests},
                         {"pair_tests", stats.pairTests},
                         {"contacts", stats.particleContacts},
                         {"evaluation_cpu_s", seconds}});
      if (!json) {
        std::printf(
            "RIGID-%s particles/object=%-7lld node_tests=%-8lld pair_tests=%-8lld "
            "contacts=%-6lld evaluation_cpu_s=%.4g\n",
            mode, static_cast<long long>(n), static_cast<long long>(stats.nodeTests),
            static_cast<long long>(stats.pairTests), static_cast<long long>(stats.particleContacts),
            seconds);
        std::fflush(stdout);
      }
    }
    const double testSlope = slopeOf(logN, logTests), timeSlope = slopeOf(logN, logTime);
    results.push_back(
        {{"mode", mode}, {"tests_loglog_slope", testSlope}, {"time_loglog_slope", timeSlope}});
    if (!json)
      std::printf("RIGID-%s log-log slope (1e3..1e5): tests %.3f, time %.3f\n", mode, testSlope,
                  timeSlope);
  }
  if (json) std::printf("%s\n", results.dump(2).c_str());
  return 0;
}

}  // namespace robophi::cli
