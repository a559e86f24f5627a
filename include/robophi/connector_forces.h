#pragma once
/// \file
/// The force laws of the three connectors (MODEL §1), one connector at a time.
// The accumulate* loops of forces.h call these; tests call them directly to
// check action/reaction and force = -grad(energy).

#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// Forces of a two-particle LS and its energy and dissipated power.
struct LinearSpringForce {
  Vec3 onA, onB;
  /// ½ κ Δl² (J).
  double energy = 0.0;
  /// Power of the damper, -μ l̇² (W).
  double dissipativePower = 0.0;
};

/// Forces of a TS on a, c, b, or of a JS on a, c, b and its reference d (zero
/// when the arms lie in the plane through c normal to the axis).
struct AngularSpringForce {
  Vec3 onA, onC, onB, onD;
  /// The connector's angle θ (rad): [0, π] for a TS, [0, 2π) for a JS.
  double angle = 0.0;
  /// ½ κ Δθ² (J).
  double energy = 0.0;
  /// Power of the damper, -μ θ̇² (W).
  double dissipativePower = 0.0;
};

LinearSpringForce linearSpringForce(const LinearSpring& spring, const Vec3& pA, const Vec3& pB,
                                    const Vec3& vA, const Vec3& vB);

AngularSpringForce torsionSpringForce(const TorsionSpring& spring, const Vec3& pA, const Vec3& pC,
                                      const Vec3& pB, const Vec3& vA, const Vec3& vC,
                                      const Vec3& vB);

AngularSpringForce jointSpringForce(const JointSpring& spring, const Vec3& pA, const Vec3& pC,
                                    const Vec3& pB, const Vec3& pD, const Vec3& vA, const Vec3& vC,
                                    const Vec3& vB, const Vec3& vD);

/// The TS angle θ = atan2(|u × w|, u·w) with u = p_a - p_c, w = p_b - p_c.
double torsionAngle(const Vec3& pA, const Vec3& pC, const Vec3& pB);
/// The JS angle in [0, 2π): the rotation from u to w about n = (p_d - p_c)/|p_d - p_c|,
/// measured between their projections on the plane normal to n.
double jointAngle(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD);
/// The JS angle's rate θ̇ = Σ_j ∂θ/∂p_j · v_j (rad/s).
double jointAngleRate(const Vec3& pA, const Vec3& pC, const Vec3& pB, const Vec3& pD,
                      const Vec3& vA, const Vec3& vC, const Vec3& vB, const Vec3& vD);

/// A joint coordinate q and its gradient ∂q/∂p at the joint's particles
/// (MODEL §1.6): a generalized force Q acts as F_j = Q ∂q/∂p_j, and q̇ = Σ ∂q/∂p_j · v_j.
/// q is unchanged by a rigid motion of the particles, so the gradients sum to
/// zero and their torques about any point balance.
struct CoordinateGradient {
  /// False where q is not differentiable (an axis or arm of length 0): no force then.
  bool valid = false;
  /// q (rad or m).
  double value = 0.0;
  /// ∂q/∂p (rad/m or -) at the connector's a, c, b and d (d unused by a prismatic joint).
  Vec3 a, c, b, d;
  /// MODEL §1.3 h: 1, except for a revolute joint whose arm leans within 14.5° of
  /// its axis, where it falls smoothly to 0 (the gradient grows as 1/|u⊥| there);
  /// a drive acts through h ∂q/∂p.
  double weight = 1.0;
  /// Σ ∂q/∂p_j · v_j (rad/s or m/s).
  double rate(const Vec3& vA, const Vec3& vC, const Vec3& vB, const Vec3& vD) const {
    return dot(a, vA) + dot(c, vC) + dot(b, vB) + dot(d, vD);
  }
};

/// The JS angle θ in [0, 2π) (jointAngle) and its exact gradient.
CoordinateGradient jointAngleGradient(const Vec3& pA, const Vec3& pC, const Vec3& pB,
                                      const Vec3& pD);

/// A prismatic joint's slider distance q = (p_c − p_a)·ê, ê = (p_b − p_a)/|p_b − p_a|
/// (a = origin, c = slider, b = end, as its TS holds them) and its gradient:
/// ∂q/∂p_c = ê, ∂q/∂p_b = (I − ê êᵀ)(p_c − p_a)/|p_b − p_a|, ∂q/∂p_a = −(∂q/∂p_c + ∂q/∂p_b).
/// On the line, ∂q/∂p_b = 0: equal and opposite forces along the line.
CoordinateGradient prismaticGradient(const Vec3& pOrigin, const Vec3& pSlider, const Vec3& pEnd);

}  // namespace robophi
