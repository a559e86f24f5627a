// The stability estimate (estimateStability) for a TS with positions: it bounds
// the TS's true ω_max from above, and stays within a small factor of it, also
// when the TS's arms are long (a path TS between far points) where the
// shortest-LS guess of the model-only estimate overstates it many times.
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

}  // namespace
}  // namespace robophi
