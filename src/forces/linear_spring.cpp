// LS: linear spring/damper (MODEL §1).
#include "robophi/connector_forces.h"
#include "forces/forces.h"

namespace robophi {

namespace {

// MODEL §1 LS: l = |p_a - p_b|, k̂ = (p_a - p_b)/l, Δl = l - l0, l̇ = (v_a - v_b)·k̂,
// F_a = (-κ Δl - μ l̇) k̂. Returns false (and no force) for coincident particles.
inline bool linearSpringKernel(const LinearSpring& s, const Vec3& pA, const Vec3& pB,
                               const Vec3& vA, const Vec3& vB, Vec3& forceOnA, double& energy,
                               double& power) {
  const Vec3 delta = pA - pB;
  const double length = norm(delta);
  if (!(length > 0.0)) return false;
  const Vec3 kHat = delta * (1.0 / length);
  const double stretch = length - s.restLength;
  const double stretchRate = dot(vA - vB, kHat);
  const double dampingForce = s.damping * stretchRate;
  forceOnA = kHat * (-s.stiffness * stretch - dampingForce);
  energy = 0.5 * s.stiffness * stretch * stretch;
  power = -dampingForce * stretchRate;
  return true;
}

}  // namespace

LinearSpringForce linearSpringForce(const LinearSpring& spring, const Vec3& pA, const Vec3& pB,
                                    const Vec3& vA, const Vec3& vB) {
  LinearSpringForce result;
  if (linearSpringKernel(spring, pA, pB, vA, vB, result.onA, result.energy,
                         result.dissipativePower)) {
    result.onB = -result.onA;
  }
  return result;
}

ForceTally accumulateLinearSprings(const Model& model, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force) {
  ForceTally tally;
  for (const LinearSpring& s : model.linearSprings) {
    Vec3 forceOnA;
    double energy = 0.0, power = 0.0;
    if (!linearSpringKernel(s, position[s.a], position[s.b], velocity[s.a], velocity[s.b], forceOnA,
                            energy, power)) {
      continue;
    }
    force[s.a] += forceOnA;
    force[s.b] -= forceOnA;
    tally.potential += energy;
    tally.dissipativePower += power;
  }
  return tally;
}

}  // namespace robophi
