// TS and JS: torsion and joint spring/dampers (MODEL §1), in gradient form so
// that the forces sum to zero, their torques sum to zero, and F = -grad(energy).
#include <cmath>
#include <numbers>

#include "core/parallel.h"
#include "forces/forces.h"
#include "robophi/connector_forces.h"

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

// MODEL §1 JS, measured about the axis: with n = (p_d - p_c)/|p_d - p_c|,
//   y = (u × w)·n,  x = u·w - (u·n)(w·n)      (= u⊥·w⊥, u⊥ the part of u normal to n)
//   θ = atan2(y, x) in [0, 2π)
// equals acos(û·ŵ) or 2π - acos(û·ŵ) of MODEL §1 when the arms are normal to n,
// and stays smooth when they are not (the sign of (u × w)·n alone would flip
// the angle between θ and 2π - θ as the arms pass through a straight line).
// The gradient is exact in all four particles, so the forces sum to zero,
// their torques sum to zero, and F = -grad(E); the force on d is zero when the
// arms lie in the plane through c normal to the axis.
struct JointGeometry {
  bool valid = false;
  double angle = 0.0;
  Vec3 gradA, gradB, gradC, gradD;
  // MODEL §1.3 weight h: 1, and its gradient zero, unless an arm leans within
  // kArmLean of the axis.
  double weight = 1.0;
  Vec3 weightA, weightB, weightC, weightD;
};

// MODEL §1.3: the angle's gradient grows as 1/|u⊥| when an arm leans onto the
// axis, where the angle is undefined. The JS's energy is weighted by
// h = g(s_u) g(s_w), s = |arm⊥|² / |arm|² (sin² of the arm's angle to the
// axis), g(s) = smoothstep(s / kArmLean²): 1 for arms at more than
// asin(kArmLean) from the axis (every joint as built), falling smoothly to 0 on
// the axis, so that the force stays bounded in a crushed lattice.
constexpr double kArmLean = 0.25;
constexpr double kArmLeanSquared = kArmLean * kArmLean;

// g(s) and g'(s) for s = sin² of an arm's angle to the axis.
inline void leanWeight(double s, double& g, double& slope) {
  const double x = s / kArmLeanSquared;
  if (x >= 1.0) {
    g = 1.0;
    slope = 0.0;
    return;
  }
  const double clamped = std::max(x, 0.0);
  g = clamped * clamped * (3.0 - 2.0 * clamped);
  slope = 6.0 * clamped * (1.0 - clamped) / kArmLeanSquared;
}

// ∂s/∂arm and ∂s/∂axis of s = 1 − (arm·n)² / |arm|², n = axis / |axis|.
inline void leanGradient(const Vec3& arm, double armN, double armSquared, const Vec3& n,
                         double axisLength, Vec3& onArm, Vec3& onAxis) {
  const double scale = 2.0 * armN / armSquared;
  onArm = (arm * (armN / armSquared) - n) * scale;
  onAxis = (arm - n * armN) * (-scale / axisLength);
}

JointGeometry jointGeometry(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD) {
  JointGeometry g;
  const Vec3 u = pA - pC, w = pB - pC, axis = pD - pC;
  const double axisLength = norm(axis);
  if (!(axisLength > 0.0)) return g;
  const Vec3 n = axis * (1.0 / axisLength);
  const double uN = dot(u, n), wN = dot(w, n);
  const double y = dot(cross(u, w), n);
  const double x = dot(u, w) - uN * wN;
  double angle = std::atan2(y, x);
  if (angle < 0.0) angle += kTwoPi;
  if (angle >= kTwoPi) angle -= kTwoPi;
  g.angle = angle;
  // x² + y² = |u⊥|² |w⊥|²: zero when an arm lies along the axis.
  const double r2 = x * x + y * y;
  if (!(r2 > kDegenerateSine * kDegenerateSine * squaredNorm(u) * squaredNorm(w))) {
    // An arm on the axis: h = 0 there (an arm of length 0 has no direction: as before).
    if (squaredNorm(u) > 0.0 && squaredNorm(w) > 0.0) g.weight = 0.0;
    return g;
  }
  // dθ = (x dy - y dx) / (x² + y²).
  const double cx = -y / r2, cy = x / r2;
  g.gradA = cross(w, n) * cy + (w - n * wN) * cx;
  g.gradB = cross(n, u) * cy + (u - n * uN) * cx;
  const Vec3 gradN = cross(u, w) * cy - (u * wN + w * uN) * cx;
  // Through n = axis/|axis|: ∂θ/∂axis = (I - n nᵀ) ∂θ/∂n / |axis|.
  g.gradD = (gradN - n * dot(n, gradN)) * (1.0 / axisLength);
  g.gradC = -(g.gradA + g.gradB + g.gradD);
  g.valid = true;
  const double uSquared = squaredNorm(u), wSquared = squaredNorm(w);
  const double sU = 1.0 - uN * uN / uSquared, sW = 1.0 - wN * wN / wSquared;
  if (sU >= kArmLeanSquared && sW >= kArmLeanSquared) return g;
  double gU = 0.0, slopeU = 0.0, gW = 0.0, slopeW = 0.0;
  leanWeight(sU, gU, slopeU);
  leanWeight(sW, gW, slopeW);
  Vec3 uArm, uAxis, wArm, wAxis;
  leanGradient(u, uN, uSquared, n, axisLength, uArm, uAxis);
  leanGradient(w, wN, wSquared, n, axisLength, wArm, wAxis);
  g.weight = gU * gW;
  g.weightA = uArm * (slopeU * gW);
  g.weightB = wArm * (gU * slopeW);
  g.weightD = uAxis * (slopeU * gW) + wAxis * (gU * slopeW);
  g.weightC = -(g.weightA + g.weightB + g.weightD);
  return g;
}

double jointRate(const JointGeometry& g, const Vec3& vA, const Vec3& vC, const Vec3& vB,
                 const Vec3& vD) {
  return dot(g.gradA, vA) + dot(g.gradB, vB) + dot(g.gradC, vC) + dot(g.gradD, vD);
}

}  // namespace

CoordinateGradient jointAngleGradient(const Vec3& pA, const Vec3& pC, const Vec3& pB,
                                      const Vec3& pD) {
  const JointGeometry g = jointGeometry(pA, pC, pB, pD);
  CoordinateGradient out;
  out.valid = g.valid;
  out.value = g.angle;
  if (!g.valid) return out;
  out.a = g.gradA;
  out.b = g.gradB;
  out.c = g.gradC;
  out.d = g.gradD;
  out.weight = g.weight;
  return out;
}

CoordinateGradient prismaticGradient(const Vec3& pOrigin, const Vec3& pSlider, const Vec3& pEnd) {
  CoordinateGradient out;
  const Vec3 line = pEnd - pOrigin, r = pSlider - pOrigin;
  const double length = norm(line);
  if (!(length > 0.0)) return out;
  const Vec3 e = line * (1.0 / length);
  out.value = dot(r, e);
  out.valid = true;
  // MODEL §1.6: q = r·ê; through ê = line/|line|, ∂q/∂line = (I − ê êᵀ) r / |line|.
  out.c = e;
  out.b = (r - e * out.value) * (1.0 / length);
  out.a = -(out.c + out.b);
  return out;
}

double jointAngle(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD) {
  return jointGeometry(pA, pC, pB, pD).angle;
}

double jointAngleRate(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD,
                      const Vec3& vA, const Vec3& vC, const Vec3& vB, const Vec3& vD) {
  const JointGeometry g = jointGeometry(pA, pC, pB, pD);
  return g.valid ? jointRate(g, vA, vC, vB, vD) : 0.0;
}

AngularSpringForce jointSpringForce(const JointSpring& spring, const Vec3& pA, const Vec3& pC,
                                    const Vec3& pB, const Vec3& pD, const Vec3& vA, const Vec3& vC,
                                    const Vec3& vB, const Vec3& vD) {
  AngularSpringForce out;
  const JointGeometry g = jointGeometry(pA, pC, pB, pD);
  out.angle = g.angle;
  // The spring pulls the short way round: Δθ wrapped into (-π, π].
  double angleError = g.angle - spring.restAngle;
  if (angleError > std::numbers::pi) angleError -= kTwoPi;
  if (angleError <= -std::numbers::pi) angleError += kTwoPi;
  const double energy = 0.5 * spring.stiffness * angleError * angleError;
  out.energy = energy * g.weight;
  if (!g.valid) return out;
  // F_j = -(κ Δθ + μ θ̇) ∂θ/∂p_j.
  const double angleRate = jointRate(g, vA, vC, vB, vD);
  const double generalizedForce = -(spring.stiffness * angleError + spring.damping * angleRate);
  // MODEL §1.3: U = h ½ κ Δθ², F_j = h Q ∂θ/∂p_j − ½ κ Δθ² ∂h/∂p_j (h = 1 and
  // ∂h/∂p = 0, the same bits as without it, unless an arm leans onto the axis).
  const double weighted = generalizedForce * g.weight;
  out.onA = g.gradA * weighted - g.weightA * energy;
  out.onB = g.gradB * weighted - g.weightB * energy;
  out.onC = g.gradC * weighted - g.weightC * energy;
  out.onD = g.gradD * weighted - g.weightD * energy;
  out.dissipativePower = -spring.damping * angleRate * angleRate * g.weight;
  return out;
}

namespace {

// The connectors' forces f(k) for k in [0, count): on the threads into
// scratch.angularForce when there are enough of them, then add(k, f(k)) in
// ascending k on this thread; serially add(k, f(k)) one by one otherwise.
template <class Force, class Add>
void angularSprings(int threads, std::size_t count, ForceScratch& scratch, const Force& forceOf,
                    const Add& add) {
  if (threads <= 1 || count < static_cast<std::size_t>(detail::kParallelMinimum)) {
    for (std::size_t k = 0; k < count; ++k) add(k, forceOf(k));
    return;
  }
  std::vector<AngularSpringForce>& buffer = scratch.angularForce;
  buffer.resize(count);
  detail::parallelFor(
      threads, static_cast<std::int64_t>(count), [&](std::int64_t begin, std::int64_t end) {
        for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k)
          buffer[k] = forceOf(k);
      });
  for (std::size_t k = 0; k < count; ++k) add(k, buffer[k]);
}

}  // namespace

ForceTally accumulateTorsionSprings(const Model& model, int threads,
                                    const std::vector<Vec3>& position,
                                    const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                    ForceScratch& scratch) {
  ForceTally tally;
  const std::vector<TorsionSpring>& springs = model.torsionSprings;
  angularSprings(
      threads, springs.size(), scratch,
      [&](std::size_t k) {
        const TorsionSpring& s = springs[k];
        return torsionSpringForce(s, position[s.a], position[s.c], position[s.b], velocity[s.a],
                                  velocity[s.c], velocity[s.b]);
      },
      [&](std::size_t k, const AngularSpringForce& f) {
        const TorsionSpring& s = springs[k];
        force[s.a] += f.onA;
        force[s.b] += f.onB;
        force[s.c] += f.onC;
        tally.potential += f.energy;
        tally.dissipativePower += f.dissipativePower;
      });
  return tally;
}

ForceTally accumulateJointSprings(const Model& model, int threads,
                                  const std::vector<Vec3>& position,
                                  const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                  ForceScratch& scratch) {
  ForceTally tally;
  const std::vector<JointSpring>& springs = model.jointSprings;
  angularSprings(
      threads, springs.size(), scratch,
      [&](std::size_t k) {
        const JointSpring& s = springs[k];
        return jointSpringForce(s, position[s.a], position[s.c], position[s.b], position[s.d],
                                velocity[s.a], velocity[s.c], velocity[s.b], velocity[s.d]);
      },
      [&](std::size_t k, const AngularSpringForce& f) {
        const JointSpring& s = springs[k];
        force[s.a] += f.onA;
        force[s.b] += f.onB;
        force[s.c] += f.onC;
        force[s.d] += f.onD;
        tally.potential += f.energy;
        tally.dissipativePower += f.dissipativePower;
      });
  return tally;
}

}  // namespace robophi
