// The stability estimate (estimateStability) for a TS with positions: it bounds
// the TS's true ω_max from above, and stays within a small factor of it, also
// when the TS's arms are long (a path TS between far points) where the
// shortest-LS guess of the model-only estimate overstates it many times. And
// the Taylor scheme's own bound (StabilityEstimate::taylorStep), against the
// damped pair whose threshold is known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "robophi/world.h"

namespace robophi {
namespace {

// Three unit-mass particles: a at distance u from the vertex c, b at w, at a right
// angle; a TS of κ = 10 N·m/rad, and one negligible LS so the refined estimate runs.
struct Case {
  double u, w;
};

TEST(Stability, TorsionSpringEstimateBoundsItsTrueFrequency) {
  for (const Case k : {Case{1.0, 1.0}, Case{0.5, 3.0}, Case{0.1, 0.1}}) {
    Model model;
    model.gravity = {};
    const int object = model.addObject("ts", "particles");
    for (int i = 0; i < 3; ++i) model.addParticle(1.0, 0.01, false, object);
    const double kappa = 10.0;
    model.torsionSprings.push_back({0, 2, 1, M_PI / 2.0, kappa, 0.0});  // a = 0, c = 2, b = 1
    model.linearSprings.push_back({0, 1, std::hypot(k.u, k.w), 1e-12, 0.0});
    const std::vector<Vec3> position = {{k.u, 0.0, 0.0}, {0.0, k.w, 0.0}, {0.0, 0.0, 0.0}};
    const StabilityEstimate estimate = estimateStability(model, &position);
    // Linearised, the TS is κ g gᵀ on the in-plane perpendicular displacements,
    // g = (1/u, -(1/u + 1/w), 1/w): unit masses, so ω_max² = κ |g|².
    const double s = 1.0 / k.u + 1.0 / k.w;
    const double exact = kappa * (1.0 / (k.u * k.u) + s * s + 1.0 / (k.w * k.w));
    const double omegaSquared = estimate.omegaMax * estimate.omegaMax;
    std::printf("u %.2f w %.2f: estimate omega^2 %.4g, exact %.4g\n", k.u, k.w, omegaSquared,
                exact);
    EXPECT_GE(omegaSquared, exact * (1.0 - 1e-9)) << "u " << k.u << " w " << k.w;
    EXPECT_LE(omegaSquared, 2.0 * exact) << "u " << k.u << " w " << k.w;
  }
}

// Two 1 kg particles on a 1e4 N/m LS (ω² = 2κ/m, which Gershgorin gives
// exactly here), damped either by the LS (c = 10 N·s/m: the mode's rate
// γ = 2c/m = τ ω², τ = c/κ) or by the particles (c = 10 each: γ = c/m). The
// Taylor step matrix has determinant 1 - γδ + (ωδ)²/2: stable exactly while
// δ < 2γ/ω², i.e. 2τ = 2e-3 s and 2 (c/m)/ω² = 1e-3 s. The estimate gives these
// bounds, and they are real: at 0.9 of them the oscillation decays, at 1.1 it
// grows (by e^±7 over 2 000 steps with the LS's damping, e^±18 over 20 000
// with the particles').
TEST(Stability, TaylorSchemeIsStableExactlyBelowItsBound) {
  for (const bool connectorDamping : {true, false}) {
    Model model;
    model.gravity = {};
    const int object = model.addObject("pair", "particles");
    for (int i = 0; i < 2; ++i) model.addParticle(1.0, 0.05, false, object);
    if (!connectorDamping) model.linearDamping = {10.0, 10.0};
    model.linearSprings.push_back({0, 1, 1.0, 1e4, connectorDamping ? 10.0 : 0.0});
    const double bound = connectorDamping ? 2.0 * 10.0 / 1e4 : 2.0 * (10.0 / 1.0) / 2e4;
    const StabilityEstimate estimate = estimateStability(model);
    EXPECT_NEAR(estimate.taylorStep, bound, 1e-12 * bound);
    EXPECT_NEAR(criticalStepFor(estimate, true), bound, 1e-12 * bound);
    EXPECT_EQ(criticalStepFor(estimate, false), estimate.criticalStep);
    for (const double factor : {0.9, 1.1}) {
      State state = State::sizedFor(model);
      state.position[1] = {1.01, 0.0, 0.0};
      World world(model, std::move(state), Integrator::kTaylor);
      const double start = world.energy().mechanical();
      const int steps = connectorDamping ? 2000 : 20000;
      for (int k = 0; k < steps; ++k) world.step(factor * bound);
      const double ratio = world.energy().mechanical() / start;
      std::printf("%s damping, step %.1f x the Taylor bound %.3g s: energy x %.3g\n",
                  connectorDamping ? "connector" : "particle", factor, bound, ratio);
      if (factor < 1.0) {
        EXPECT_LT(ratio, 1e-3);
      } else {
        EXPECT_GT(ratio, 1e3);
      }
    }
  }
  // Undamped: no step is stable (0), and the Taylor cap falls back on the
  // symplectic one (the adaptive step's energy test judges).
  Model model;
  model.gravity = {};
  const int object = model.addObject("pair", "particles");
  for (int i = 0; i < 2; ++i) model.addParticle(1.0, 0.05, false, object);
  model.linearSprings.push_back({0, 1, 1.0, 1e4, 0.0});
  const StabilityEstimate estimate = estimateStability(model);
  EXPECT_EQ(estimate.taylorStep, 0.0);
  EXPECT_EQ(criticalStepFor(estimate, true), estimate.criticalStep);
}

}  // namespace
}  // namespace robophi
