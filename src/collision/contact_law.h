#pragma once
// The contact laws, written once (issue 36; docs/contact.md "The stage"):
// MODEL §3.1's normal force, §3.3's anchor damping and friction laws and §3.7's
// stability rates of one contact. The scalar stage (contact_force.cpp) and the
// rigid trees' implicit terms (integrate/rigid_trees.cpp) call these; the AVX2
// lanes (pair_lanes.cpp) mirror them operation by operation (each of their
// functions carries the AVX2 target, which a shared template cannot). `Ops`
// names the number type N (and vector type V) and its operations, each one
// IEEE operation (add, sub, mul, div, sqrt, negate, atLeastZero: x < 0 ? 0 : x,
// maxOf: a < b ? b : a, constant; scaleV, subV, dotV).

#include <cmath>

namespace robophi::law {

/// MODEL §3.1 for one contact: the normal force F_n (N), its spring's energy (J)
/// and the power of its non-elastic part (W, dissipated).
template <class N>
struct NormalLoad {
  N force, potential, dissipation;
};

/// F_n = -κ_c d - μ_c ḋ clamped at >= 0 (a damper that would pull is clamped);
/// ½ κ_c d²; (F_n + κ_c d) ḋ, the damper's power or the clamp's.
template <class Ops>
[[gnu::always_inline]] inline NormalLoad<typename Ops::N> normalLaw(typename Ops::N stiffness,
                                                                    typename Ops::N damping,
                                                                    typename Ops::N depth,
                                                                    typename Ops::N depthRate) {
  using N = typename Ops::N;
  const N force = Ops::atLeastZero(
      Ops::sub(Ops::mul(Ops::negate(stiffness), depth), Ops::mul(damping, depthRate)));
  const N potential = Ops::mul(Ops::mul(Ops::mul(Ops::constant(0.5), stiffness), depth), depth);
  const N dissipation = Ops::mul(Ops::add(force, Ops::mul(stiffness, depth)), depthRate);
  return {force, potential, dissipation};
}

/// MODEL §3.3: the anchor's damping c_t = ratio × 2 √(k_t m_eff) (N·s/m), from
/// k_t and the contact point's inverse effective mass 1/m_eff.
template <class Ops>
[[gnu::always_inline]] inline typename Ops::N tangentialDamping(typename Ops::N ratio,
                                                                typename Ops::N tangentialStiffness,
                                                                typename Ops::N inverseMass) {
  return Ops::mul(Ops::mul(ratio, Ops::constant(2.0)),
                  Ops::sqrt(Ops::div(tangentialStiffness, inverseMass)));
}

/// MODEL §3.7: what one contact adds to its particles' stability sums, the
/// larger of its normal and tangential stiffness (N/m) and damping (N·s/m), the
/// tangential ones scaled to the particles' mass by `rotation`, (1/m_eff) / (1/m)
/// (> 1 where the contact point also turns). (A contact between fixed sides adds
/// nothing: its callers' test.)
template <class N>
struct Rates {
  N stiffness, damping;
};
template <class Ops>
[[gnu::always_inline]] inline Rates<typename Ops::N> stabilityRates(
    typename Ops::N stiffness, typename Ops::N damping, typename Ops::N tangentialStiffness,
    typename Ops::N tangentialDamping, typename Ops::N rotation) {
  return {Ops::maxOf(stiffness, Ops::mul(tangentialStiffness, rotation)),
          Ops::maxOf(damping, Ops::mul(tangentialDamping, rotation))};
}

/// MODEL §3.3, friction that holds: sticking (scale 1) or breaking away (scale
/// μ_s Σ F_n / Σ|F_t| < 1, the group's). The anchor gives way to scale × δ_t
/// (anchor = relative - scale δ_t); the friction force is scale × (the anchor
/// spring's and damper's load); the anchor keeps ½ k_t |scale δ_t|² (J); the
/// damper dissipates scale c_t |v_t|² (W). `Ops::V` is the vector type
/// (scaleV, subV, dotV).
/// (FrictionLoad: what either friction law gives a contact.)
template <class N, class V>
struct FrictionLoad {
  V anchor, force;
  N anchorEnergy, dissipated;
};
template <class Ops>
[[gnu::always_inline]] inline FrictionLoad<typename Ops::N, typename Ops::V> heldFriction(
    const typename Ops::V& relative, const typename Ops::V& delta,
    const typename Ops::V& tangentialLoad, typename Ops::N scale,
    typename Ops::N tangentialStiffness, typename Ops::N tangentialDamping,
    typename Ops::N slipSpeed) {
  const typename Ops::V held = Ops::scaleV(delta, scale);
  return {Ops::subV(relative, held), Ops::scaleV(tangentialLoad, scale),
          Ops::mul(Ops::mul(Ops::constant(0.5), tangentialStiffness), Ops::dotV(held, held)),
          Ops::mul(Ops::mul(Ops::mul(scale, tangentialDamping), slipSpeed), slipSpeed)};
}

/// MODEL §3.3, sliding: F_t = -μ_k F_n ŝ (ŝ the unit slip direction, or the
/// held load's where the slip stopped); the anchor trails the contact at the
/// offset that spring would hold, μ_k F_n / k_t along ŝ, and keeps ½ k_t of its
/// square (J); kinetic friction dissipates μ_k F_n |v_t| (W).
template <class Ops>
[[gnu::always_inline]] inline FrictionLoad<typename Ops::N, typename Ops::V> slidingFriction(
    const typename Ops::V& relative, const typename Ops::V& direction,
    typename Ops::N kineticFriction, typename Ops::N normalForce,
    typename Ops::N tangentialStiffness, typename Ops::N slipSpeed) {
  const typename Ops::N friction = Ops::mul(kineticFriction, normalForce);
  const typename Ops::V consistent =
      Ops::scaleV(direction, Ops::div(friction, tangentialStiffness));
  return {Ops::subV(relative, consistent), Ops::scaleV(direction, Ops::negate(friction)),
          Ops::mul(Ops::mul(Ops::constant(0.5), tangentialStiffness),
                   Ops::dotV(consistent, consistent)),
          Ops::mul(friction, slipSpeed)};
}

/// The scalar operations (a template, so that none is compiled where it is not used).
template <class T>
struct BasicScalarOps {
  using N = T;
  static T add(T a, T b) { return a + b; }
  static T sub(T a, T b) { return a - b; }
  static T mul(T a, T b) { return a * b; }
  static T div(T a, T b) { return a / b; }
  static T sqrt(T a) { return std::sqrt(a); }
  static T negate(T a) { return -a; }
  static T atLeastZero(T a) { return a < T(0) ? T(0) : a; }
  static T maxOf(T a, T b) { return a < b ? b : a; }
  static T constant(double a) { return T(a); }
};
using ScalarOps = BasicScalarOps<double>;

}  // namespace robophi::law
