// TS and JS: torsion and joint spring/dampers (MODEL §1), in gradient form so
// that the forces sum to zero, their torques sum to zero, and F = -grad(energy).
#include <cmath>
#include <numbers>

#include "forces/connector_forces.h"
#include "forces/forces.h"

namespace robophi {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Below this |u × w| / (|u| |w|) the plane of the arms is taken as undefined.
constexpr double kDegenerateSine = 1e-14;

// The gradient of an angle θ measured from u = p_a - p_c to w = p_b - p_c,
// positive about the unit normal m (MODEL §1 TS):
// ∂θ/∂p_a = -(m × û)/|u|,  ∂θ/∂p_b = (m × ŵ)/|w|,  ∂θ/∂p_c = -(∂θ/∂p_a + ∂θ/∂p_b).
struct AngleGradient {
  Vec3 a, b, c;
};

AngleGradient angleGradient(const Vec3& m, const Vec3& u, double uLength, const Vec3& w,
                            double wLength) {
  AngleGradient g;
  g.a = cross(m, u) * (-1.0 / (uLength * uLength));
  g.b = cross(m, w) * (1.0 / (wLength * wLength));
  g.c = -(g.a + g.b);
  return g;
}

// F_j = -(κ Δθ + μ θ̇) ∂θ/∂p_j, θ̇ = Σ_j ∂θ/∂p_j · v_j.
void applyAngularLaw(const AngleGradient& g, double angleError, double stiffness, double damping,
                     const Vec3& vA, const Vec3& vC, const Vec3& vB, AngularSpringForce& out) {
  const double angleRate = dot(g.a, vA - vC) + dot(g.b, vB - vC);
  const double generalizedForce = -(stiffness * angleError + damping * angleRate);
  out.onA = g.a * generalizedForce;
  out.onB = g.b * generalizedForce;
  out.onC = g.c * generalizedForce;
  out.dissipativePower = -damping * angleRate * angleRate;
}

}  // namespace

double torsionAngle(const Vec3& pA, const Vec3& pC, const Vec3& pB) {
  const Vec3 u = pA - pC, w = pB - pC;
  return std::atan2(norm(cross(u, w)), dot(u, w));
}

AngularSpringForce torsionSpringForce(const TorsionSpring& spring, const Vec3& pA, const Vec3& pC,
                                      const Vec3& pB, const Vec3& vA, const Vec3& vC,
                                      const Vec3& vB) {
  AngularSpringForce out;
  const Vec3 u = pA - pC, w = pB - pC;
  const Vec3 uxw = cross(u, w);
  const double sine = norm(uxw);
  const double uLength = norm(u), wLength = norm(w);
  out.angle = std::atan2(sine, dot(u, w));
  const double angleError = out.angle - spring.restAngle;
  out.energy = 0.5 * spring.stiffness * angleError * angleError;
  // MODEL §1: at θ = 0 or π the plane is undefined; the force there tends to 0
  // for θ0 = π (a prismatic joint), and is skipped otherwise.
  if (!(uLength > 0.0) || !(wLength > 0.0) || sine <= kDegenerateSine * uLength * wLength) {
    return out;
  }
  const AngleGradient g = angleGradient(uxw / sine, u, uLength, w, wLength);
  applyAngularLaw(g, angleError, spring.stiffness, spring.damping, vA, vC, vB, out);
  return out;
}

namespace {

// MODEL §1 JS: θ = acos(û·ŵ) if (û × ŵ)·n >= 0, else 2π - acos(û·ŵ), with its
// gradient. `valid` is false when an arm or the axis has zero length.
struct JointGeometry {
  bool valid = false;
  double angle = 0.0;
  AngleGradient gradient;
};

JointGeometry jointGeometry(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD) {
  JointGeometry geometry;
  const Vec3 u = pA - pC, w = pB - pC, axis = pD - pC;
  const double uLength = norm(u), wLength = norm(w), axisLength = norm(axis);
  if (!(uLength > 0.0) || !(wLength > 0.0) || !(axisLength > 0.0)) return geometry;
  const Vec3 n = axis / axisLength;
  const Vec3 uxw = cross(u, w);
  const double sine = norm(uxw);
  const double unsignedAngle = std::atan2(sine, dot(u, w));
  const bool positive = dot(uxw, n) >= 0.0;
  geometry.angle = positive ? unsignedAngle : kTwoPi - unsignedAngle;
  if (geometry.angle >= kTwoPi) geometry.angle -= kTwoPi;

  // Oriented normal of the arms' plane; where that plane is undefined (arms
  // aligned) the joint axis, made perpendicular to u, orients the rotation.
  Vec3 m;
  if (sine > kDegenerateSine * uLength * wLength) {
    m = uxw * ((positive ? 1.0 : -1.0) / sine);
  } else {
    const Vec3 uHat = u / uLength;
    const Vec3 nPerp = n - uHat * dot(n, uHat);
    const double nPerpLength = norm(nPerp);
    if (!(nPerpLength > kDegenerateSine)) return geometry;
    m = nPerp / nPerpLength;
  }
  geometry.gradient = angleGradient(m, u, uLength, w, wLength);
  geometry.valid = true;
  return geometry;
}

}  // namespace

double jointAngle(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD) {
  return jointGeometry(pA, pC, pB, pD).angle;
}

double jointAngleRate(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD,
                      const Vec3& vA, const Vec3& vC, const Vec3& vB) {
  const JointGeometry geometry = jointGeometry(pA, pC, pB, pD);
  if (!geometry.valid) return 0.0;
  return dot(geometry.gradient.a, vA - vC) + dot(geometry.gradient.b, vB - vC);
}

AngularSpringForce jointSpringForce(const JointSpring& spring, const Vec3& pA, const Vec3& pC,
                                    const Vec3& pB, const Vec3& pD, const Vec3& vA,
                                    const Vec3& vC, const Vec3& vB) {
  AngularSpringForce out;
  const JointGeometry geometry = jointGeometry(pA, pC, pB, pD);
  out.angle = geometry.angle;
  // The spring pulls the short way round: Δθ wrapped into (-π, π].
  double angleError = geometry.angle - spring.restAngle;
  if (angleError > std::numbers::pi) angleError -= kTwoPi;
  if (angleError <= -std::numbers::pi) angleError += kTwoPi;
  out.energy = 0.5 * spring.stiffness * angleError * angleError;
  if (!geometry.valid) return out;
  applyAngularLaw(geometry.gradient, angleError, spring.stiffness, spring.damping, vA, vC, vB,
                  out);
  return out;
}

ForceTally accumulateTorsionSprings(const Model& model, const std::vector<Vec3>& position,
                                    const std::vector<Vec3>& velocity, std::vector<Vec3>& force) {
  ForceTally tally;
  for (const TorsionSpring& s : model.torsionSprings) {
    const AngularSpringForce f = torsionSpringForce(s, position[s.a], position[s.c], position[s.b],
                                                    velocity[s.a], velocity[s.c], velocity[s.b]);
    force[s.a] += f.onA;
    force[s.b] += f.onB;
    force[s.c] += f.onC;
    tally.potential += f.energy;
    tally.dissipativePower += f.dissipativePower;
  }
  return tally;
}

ForceTally accumulateJointSprings(const Model& model, const std::vector<Vec3>& position,
                                  const std::vector<Vec3>& velocity, std::vector<Vec3>& force) {
  ForceTally tally;
  for (const JointSpring& s : model.jointSprings) {
    const AngularSpringForce f =
        jointSpringForce(s, position[s.a], position[s.c], position[s.b], position[s.d],
                         velocity[s.a], velocity[s.c], velocity[s.b]);
    force[s.a] += f.onA;
    force[s.b] += f.onB;
    force[s.c] += f.onC;
    tally.potential += f.energy;
    tally.dissipativePower += f.dissipativePower;
  }
  return tally;
}

}  // namespace robophi
