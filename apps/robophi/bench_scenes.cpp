#include "bench_scenes.h"

#include <fmt/format.h>

#include <cmath>

#include "bench_pile.h"

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

}  // namespace robophi::cli
