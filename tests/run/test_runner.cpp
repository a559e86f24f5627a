// The runner reports numerical trouble instead of a silent garbage result.
#include <gtest/gtest.h>

#include <cmath>

#include "run/runner.h"

namespace robophi {
namespace {

// Two particles on a stiff LS, stretched, run with a constant step far above 2/ω.
Scene stiffSpringPair(double dt, double duration) {
  Scene scene;
  scene.name = "stiff pair";
  Model& model = scene.model;
  model.gravity = {};
  const int object = model.addObject("pair", "particles");
  model.addParticle(1.0, 0.05, false, object);
  model.addParticle(1.0, 0.05, false, object);
  model.linearSprings.push_back({0, 1, 1.0, 1.0e4, 0.0});
  scene.initial = State::sizedFor(model);
  scene.initial.position[1] = {1.1, 0.0, 0.0};
  scene.run.stepMode = StepMode::kConstant;
  scene.run.integrator = Integrator::kSymplecticEuler;
  scene.run.dt = dt;
  scene.run.duration = duration;
  return scene;
}

TEST(Runner, RunawayEnergyIsReportedAsDivergence) {
  // ω = sqrt(2κ/m) = 141 rad/s: 2/ω = 14 ms. At 20 ms the energy grows by about
  // 3× a step; 12 steps stay finite but are garbage.
  const Scene scene = stiffSpringPair(0.02, 0.24);
  RunOptions options;
  options.settings = scene.run;
  const RunReport report = runScene(scene, options);
  EXPECT_TRUE(std::isfinite(report.finalTotal));
  EXPECT_EQ(report.status, "diverged");
  EXPECT_NE(report.failure.find("energy grew"), std::string::npos) << report.failure;
  EXPECT_EQ(preflightWarnings(scene.run, report.stability).size(), 1u);
}

TEST(Runner, NonFiniteStateIsReportedWithTheParticle) {
  const Scene scene = stiffSpringPair(0.02, 100.0);
  RunOptions options;
  options.settings = scene.run;
  const RunReport report = runScene(scene, options);
  EXPECT_EQ(report.status, "diverged");
  EXPECT_NE(report.failure.find("non-finite"), std::string::npos) << report.failure;
}

TEST(Runner, AStableRunIsOk) {
  const Scene scene = stiffSpringPair(1e-4, 0.5);
  RunOptions options;
  options.settings = scene.run;
  const RunReport report = runScene(scene, options);
  EXPECT_TRUE(report.ok()) << report.failure;
  EXPECT_TRUE(preflightWarnings(scene.run, report.stability).empty());
  EXPECT_LT(std::abs(report.energyDrift), 0.02);  // symplectic Euler: about ωδ/2
}

}  // namespace
}  // namespace robophi
