// The stability estimate of MODEL §2: δ < 2/ω_max for the symplectic schemes.
#include <cmath>
#include <limits>
#include <vector>

#include "robophi/world.h"

namespace robophi {

bool parseIntegrator(const std::string& name, Integrator& out) {
  if (name == "taylor" || name == "paper") {
    out = Integrator::kTaylor;
  } else if (name == "symplectic" || name == "symplectic-euler") {
    out = Integrator::kSymplecticEuler;
  } else if (name == "verlet" || name == "velocity-verlet") {
    out = Integrator::kVelocityVerlet;
  } else {
    return false;
  }
  return true;
}

const char* integratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::kTaylor:
      return "taylor";
    case Integrator::kSymplecticEuler:
      return "symplectic";
    case Integrator::kVelocityVerlet:
      return "verlet";
  }
  return "unknown";
}

StabilityEstimate estimateStability(const Model& model) {
  // Per particle, the sum of the linear stiffness (N/m) and damping (N·s/m) of
  // the connectors that touch it. A TS or JS of stiffness κ (N·m/rad) acts on an
  // arm r like a linear spring κ/r²; r is taken as the particle's shortest LS
  // rest length (or twice its radius), which errs on the stiff side.
  const auto n = static_cast<std::size_t>(model.particleCount());
  std::vector<double> stiffness(n, 0.0), damping(model.linearDamping);
  std::vector<double> shortestArm(n, std::numeric_limits<double>::infinity());
  for (const LinearSpring& s : model.linearSprings) {
    stiffness[s.a] += s.stiffness;
    stiffness[s.b] += s.stiffness;
    damping[s.a] += s.damping;
    damping[s.b] += s.damping;
    shortestArm[s.a] = std::min(shortestArm[s.a], s.restLength);
    shortestArm[s.b] = std::min(shortestArm[s.b], s.restLength);
  }
  auto addAngular = [&](ParticleIndex p, double kappa, double mu) {
    // Never below the particle's diameter (an LS of zero rest length, e.g. an
    // attractor, sets no arm).
    const double arm = std::isfinite(shortestArm[p]) ? std::max(shortestArm[p], 2.0 * model.radius[p])
                                                     : 2.0 * model.radius[p];
    stiffness[p] += kappa / (arm * arm);
    damping[p] += mu / (arm * arm);
  };
  for (const TorsionSpring& s : model.torsionSprings) {
    for (ParticleIndex p : {s.a, s.b, s.c}) addAngular(p, s.stiffness, s.damping);
  }
  for (const JointSpring& s : model.jointSprings) {
    for (ParticleIndex p : {s.a, s.b, s.c}) addAngular(p, s.stiffness, s.damping);
  }

  // Gershgorin: ω² <= 2 Σκ / m for the particle's row of M⁻¹K; the same bound for
  // damping gives ζ, and a damped explicit step needs ω δ < 2 (√(1+ζ²) - ζ).
  StabilityEstimate estimate;
  estimate.criticalStep = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) continue;
    const double omegaSquared = 2.0 * stiffness[i] * model.inverseMass[i];
    const double omega = std::sqrt(omegaSquared);
    const double dampingRate = 2.0 * damping[i] * model.inverseMass[i];  // 2ζω
    double step = std::numeric_limits<double>::infinity();
    if (omega > 0.0) {
      const double zeta = dampingRate / (2.0 * omega);
      step = 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
    } else if (dampingRate > 0.0) {
      step = 2.0 / dampingRate;
    }
    estimate.omegaMax = std::max(estimate.omegaMax, omega);
    if (step < estimate.criticalStep) {
      estimate.criticalStep = step;
      estimate.limitingParticle = static_cast<ParticleIndex>(i);
    }
  }
  return estimate;
}

}  // namespace robophi
