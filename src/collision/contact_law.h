#pragma once
// The contact laws, written once (issue 36; docs/contact.md "The stage"):
// MODEL §3.1's normal force, §3.3's anchor damping and friction laws and §3.7's
// stability rates of one contact. The scalar stage (contact_force.cpp) and the
// rigid trees' implicit terms (integrate/rigid_trees.cpp) call these; the AVX2
// lanes (pair_lanes.cpp) mirror them operation by operation, in the same order
// (tests/collision/test_pair_lanes.cpp: the same bits).

#include <algorithm>
#include <cmath>

#include "robophi/vec3.h"

namespace robophi::law {

/// MODEL §3.1 for one contact: the normal force F_n (N), its spring's energy (J)
/// and the power of its non-elastic part (W, dissipated).
struct NormalLoad {
  double force, potential, dissipation;
};

/// F_n = -κ_c d - μ_c ḋ clamped at >= 0 (a damper that would pull is clamped);
/// ½ κ_c d²; (F_n + κ_c d) ḋ, the damper's power or the clamp's.
inline NormalLoad normalLaw(double stiffness, double damping, double depth, double depthRate) {
  double force = -stiffness * depth - damping * depthRate;
  if (force < 0.0) force = 0.0;
  return {force, 0.5 * stiffness * depth * depth, (force + stiffness * depth) * depthRate};
}

/// MODEL §3.3: the anchor's damping c_t = ratio × 2 √(k_t m_eff) (N·s/m), from
/// k_t and the contact point's inverse effective mass 1/m_eff.
inline double tangentialDamping(double ratio, double tangentialStiffness, double inverseMass) {
  return ratio * 2.0 * std::sqrt(tangentialStiffness / inverseMass);
}

/// MODEL §3.7: what one contact adds to its particles' stability sums, the
/// larger of its normal and tangential stiffness (N/m) and damping (N·s/m), the
/// tangential ones scaled to the particles' mass by `rotation`, (1/m_eff) / (1/m)
/// (> 1 where the contact point also turns). (A contact between fixed sides adds
/// nothing: its callers' test.)
/// A particle's stability sums are Rates too: Σ of its contacts' rates, each
/// contact's added by `add` (with the share of it the particle carries), the
/// one place they are summed.
struct Rates {
  double stiffness = 0.0, damping = 0.0;
  void add(const Rates& rates, double share = 1.0) {
    stiffness += rates.stiffness * share;
    damping += rates.damping * share;
  }
};
inline Rates stabilityRates(double stiffness, double damping, double tangentialStiffness,
                            double tangentialDamping, double rotation) {
  return {std::max(stiffness, tangentialStiffness * rotation),
          std::max(damping, tangentialDamping * rotation)};
}

/// What either friction law gives a contact: its new anchor (m), the friction
/// force on a (N), the anchor spring's energy (J) and the power dissipated (W).
struct FrictionLoad {
  Vec3 anchor, force;
  double anchorEnergy, dissipated;
};

/// MODEL §3.3, friction that holds: sticking (scale 1) or breaking away (scale
/// μ_s Σ F_n / Σ|F_t| < 1, the group's). The anchor gives way to scale × δ_t
/// (anchor = relative - scale δ_t); the force is scale × (the anchor spring's and
/// damper's load); the anchor keeps ½ k_t |scale δ_t|²; the damper dissipates
/// scale c_t |v_t|².
inline FrictionLoad heldFriction(const Vec3& relative, const Vec3& delta,
                                 const Vec3& tangentialLoad, double scale,
                                 double tangentialStiffness, double tangentialDamping,
                                 double slipSpeed) {
  const Vec3 held = delta * scale;
  return {relative - held, tangentialLoad * scale, 0.5 * tangentialStiffness * squaredNorm(held),
          scale * tangentialDamping * slipSpeed * slipSpeed};
}

/// MODEL §3.3, the coefficient of a contact sliding at |V| = `slipSpeed`:
/// μ_k + (μ_s - μ_k) exp(-(|V|/v_S)²) (Stribeck), continuous with breaking away
/// (μ_s) at the start of a slip and μ_k once the slip is fast against v_S; μ_k
/// at every speed when v_S = 0.
inline double slidingCoefficient(double staticFriction, double kineticFriction, double slipSpeed,
                                 double stribeckVelocity) {
  if (stribeckVelocity <= 0.0) return kineticFriction;
  const double r = slipSpeed / stribeckVelocity;
  return kineticFriction + (staticFriction - kineticFriction) * std::exp(-r * r);
}

/// MODEL §3.3, sliding: F_t = -μ F_n ŝ, μ = slidingCoefficient (ŝ the unit slip
/// direction, or the held load's where the slip stopped); the anchor trails the
/// contact at the offset that spring would hold, μ F_n / k_t along ŝ, and keeps
/// ½ k_t of its square; sliding friction dissipates μ F_n |v_t|.
inline FrictionLoad slidingFriction(const Vec3& relative, const Vec3& direction, double coefficient,
                                    double normalForce, double tangentialStiffness,
                                    double slipSpeed) {
  const double friction = coefficient * normalForce;
  const Vec3 consistent = direction * (friction / tangentialStiffness);
  return {relative - consistent, direction * -friction,
          0.5 * tangentialStiffness * squaredNorm(consistent), friction * slipSpeed};
}

}  // namespace robophi::law
