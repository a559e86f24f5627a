// The stability estimate of MODEL §2: δ < 2/ω_max for the symplectic schemes.
#include <algorithm>
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

namespace {

// λ_max of M^-1/2 K M^-1/2 (or with C, the damping) for the LS alone, linearised
// at `position` (axial stiffness κ k̂k̂ᵀ per spring), by a power iteration with the
// Rayleigh quotient. Fixed particles do not move. Deterministic start vector.
double largestLinearSpringEigenvalue(const Model& model, const std::vector<Vec3>& position,
                                     bool damping) {
  const auto n = static_cast<std::size_t>(model.particleCount());
  std::vector<double> invSqrtMass(n);
  for (std::size_t i = 0; i < n; ++i) invSqrtMass[i] = std::sqrt(model.inverseMass[i]);
  std::vector<Vec3> axis(model.linearSprings.size());
  for (std::size_t k = 0; k < axis.size(); ++k) {
    const LinearSpring& s = model.linearSprings[k];
    const Vec3 d = position[s.a] - position[s.b];
    const double length = norm(d);
    axis[k] = length > 0.0 ? d / length : Vec3{1.0, 0.0, 0.0};
  }
  std::vector<Vec3> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double f = static_cast<double>(i);
    x[i] = Vec3{std::sin(1.0 + f), std::cos(2.0 + 3.0 * f), std::sin(5.0 * f + 0.5)} *
           (invSqrtMass[i] > 0.0 ? 1.0 : 0.0);
  }
  double lambda = 0.0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    double xx = 0.0;
    for (const Vec3& v : x) xx += squaredNorm(v);
    if (!(xx > 0.0)) return 0.0;
    for (Vec3& v : y) v = Vec3{};
    for (std::size_t k = 0; k < axis.size(); ++k) {
      const LinearSpring& s = model.linearSprings[k];
      const double coefficient = damping ? s.damping : s.stiffness;
      const double stretch =
          dot(x[s.a] * invSqrtMass[s.a] - x[s.b] * invSqrtMass[s.b], axis[k]) * coefficient;
      y[s.a] += axis[k] * (stretch * invSqrtMass[s.a]);
      y[s.b] -= axis[k] * (stretch * invSqrtMass[s.b]);
    }
    double xy = 0.0, yy = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      xy += dot(x[i], y[i]);
      yy += squaredNorm(y[i]);
    }
    lambda = std::max(lambda, xy / xx);
    if (!(yy > 0.0)) break;
    const double scale = 1.0 / std::sqrt(yy);
    for (std::size_t i = 0; i < n; ++i) x[i] = y[i] * scale;
  }
  return lambda;
}

}  // namespace

double dampedCriticalStep(double omega, double dampingRate) {
  if (omega > 0.0) {
    const double zeta = dampingRate / (2.0 * omega);
    return 2.0 / omega * (std::sqrt(1.0 + zeta * zeta) - zeta);
  }
  return dampingRate > 0.0 ? 2.0 / dampingRate : std::numeric_limits<double>::infinity();
}

StabilityEstimate estimateStability(const Model& model, const std::vector<Vec3>* position) {
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
  std::vector<double> angularK(n, 0.0), angularC(n, 0.0);
  auto addAngular = [&](ParticleIndex p, double kappa, double mu) {
    // Never below the particle's diameter (an LS of zero rest length, e.g. an
    // attractor, sets no arm).
    const double arm = std::isfinite(shortestArm[p])
                           ? std::max(shortestArm[p], 2.0 * model.radius[p])
                           : 2.0 * model.radius[p];
    stiffness[p] += kappa / (arm * arm);
    damping[p] += mu / (arm * arm);
    angularK[p] += kappa / (arm * arm);
    angularC[p] += mu / (arm * arm);
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
  // The Taylor scheme's bound (StabilityEstimate::taylorStep): the least damping
  // rate c/m of a stiff particle and the least damping-to-stiffness ratio c/κ
  // of a connector (a lower bound of every mode's damping: C >= τ_min K).
  double leastRate = std::numeric_limits<double>::infinity();   // (1/s)
  double leastRatio = std::numeric_limits<double>::infinity();  // (s)
  const auto ratio = [&](double k, double c) {
    if (k > 0.0) leastRatio = std::min(leastRatio, c / k);
  };
  for (const LinearSpring& s : model.linearSprings) ratio(s.stiffness, s.damping);
  for (const TorsionSpring& s : model.torsionSprings) ratio(s.stiffness, s.damping);
  for (const JointSpring& s : model.jointSprings) ratio(s.stiffness, s.damping);
  for (std::size_t i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) continue;
    if (stiffness[i] > 0.0)
      leastRate = std::min(leastRate, model.linearDamping[i] * model.inverseMass[i]);
    const double omegaSquared = 2.0 * stiffness[i] * model.inverseMass[i];
    const double omega = std::sqrt(omegaSquared);
    const double dampingRate = 2.0 * damping[i] * model.inverseMass[i];  // 2ζω
    const double step = dampedCriticalStep(omega, dampingRate);
    estimate.omegaMax = std::max(estimate.omegaMax, omega);
    estimate.dampingRate = std::max(estimate.dampingRate, dampingRate);
    if (step < estimate.criticalStep) {
      estimate.criticalStep = step;
      estimate.limitingParticle = static_cast<ParticleIndex>(i);
    }
  }
  // Taylor's scheme on a damped oscillator x'' = -ω² x - γ x' has the step
  // matrix determinant 1 - γδ + (ωδ)²/2: stable while δ < 2γ/ω². Connector
  // damping c = τ κ damps a mode of ω at the rate τ ω².
  const auto taylorStep = [&](double omega) {
    if (!(omega > 0.0) || !std::isfinite(leastRate)) return std::numeric_limits<double>::infinity();
    return 2.0 * leastRate / (omega * omega) + 2.0 * (std::isfinite(leastRatio) ? leastRatio : 0.0);
  };
  estimate.taylorStep = taylorStep(estimate.omegaMax);
  if (position == nullptr || model.linearSprings.empty()) return estimate;

  // With positions: the LS part by power iteration instead of Gershgorin, which
  // can overestimate ω_max by a factor of two or more on braced lattices (hubs
  // with many spokes). By Weyl's inequality the TS/JS part (Gershgorin) adds on
  // top: ω² <= λ_max(LS) + max_i 2 Σκ_angular / m_i. The same for damping gives ζ.
  const double lsStiffness = largestLinearSpringEigenvalue(model, *position, false);
  const double lsDamping = largestLinearSpringEigenvalue(model, *position, true);
  // With positions, a TS's own arms u = |p_a - p_c|, w = |p_b - p_c| (never below
  // the particles' diameters) replace the shortest-LS guess: the rows of
  // κ g gᵀ, g = (1/u, -(1/u + 1/w), 1/w), sum to 2κ/u (1/u + 1/w) at a,
  // 2κ (1/u + 1/w)² at c and 2κ/w (1/u + 1/w) at b. (A path TS between far fixed
  // points was estimated 25× too stiff.)
  std::fill(angularK.begin(), angularK.end(), 0.0);
  std::fill(angularC.begin(), angularC.end(), 0.0);
  for (const TorsionSpring& s : model.torsionSprings) {
    const double u = std::max(norm((*position)[s.a] - (*position)[s.c]), 2.0 * model.radius[s.a]);
    const double w = std::max(norm((*position)[s.b] - (*position)[s.c]), 2.0 * model.radius[s.b]);
    if (!(u > 0.0 && w > 0.0)) {  // no size to go by: keep the guess
      for (ParticleIndex p : {s.a, s.b, s.c}) addAngular(p, s.stiffness, s.damping);
      continue;
    }
    const double sum = 1.0 / u + 1.0 / w;
    const double factor[3] = {sum / u, sum * sum, sum / w};
    const ParticleIndex particles[3] = {s.a, s.c, s.b};
    for (int k = 0; k < 3; ++k) {
      angularK[particles[k]] += s.stiffness * factor[k];
      angularC[particles[k]] += s.damping * factor[k];
    }
  }
  for (const JointSpring& s : model.jointSprings) {
    for (ParticleIndex p : {s.a, s.b, s.c}) addAngular(p, s.stiffness, s.damping);
  }
  double angularStiffness = 0.0, angularDamping = 0.0, particleDamping = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) continue;
    angularStiffness = std::max(angularStiffness, 2.0 * angularK[i] * model.inverseMass[i]);
    angularDamping = std::max(angularDamping, 2.0 * angularC[i] * model.inverseMass[i]);
    particleDamping = std::max(particleDamping, model.linearDamping[i] * model.inverseMass[i]);
  }
  // The power iteration approaches λ from below: 10% margin on ω².
  const double omega = std::sqrt(1.1 * lsStiffness + angularStiffness);
  const double dampingRate = 1.1 * lsDamping + angularDamping + particleDamping;  // 2ζω
  if (!(omega > 0.0)) return estimate;
  const double step = dampedCriticalStep(omega, dampingRate);
  // The estimate with positions stands on its own (it may be tighter or looser
  // than the model-only one: a TS's true arms can be longer or shorter than
  // the particle's shortest LS).
  if (std::isfinite(step)) {
    estimate.omegaMax = omega;
    estimate.dampingRate = dampingRate;
    estimate.criticalStep = step;
    estimate.taylorStep = taylorStep(omega);
  }
  return estimate;
}

double criticalStepFor(const StabilityEstimate& estimate, bool taylor) {
  if (taylor && estimate.taylorStep > 0.0)
    return std::min(estimate.criticalStep, estimate.taylorStep);
  return estimate.criticalStep;
}

}  // namespace robophi
