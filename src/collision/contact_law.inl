// The contact laws, written once over a number type S and a vector type V
// (issue 36; docs/contact.md "The stage"; STYLE 21: a fast path is written
// once). Included twice, with no include guard:
// - by collision/contact_law.h in namespace robophi::law, for doubles and Vec3
//   (the scalar stage, the rigid trees' implicit terms);
// - by collision/pair_lanes.cpp in a namespace of its own compiled for AVX2,
//   for four contacts at a time (its Lane and V3).
// Each includer first declares, for its types, the operations these use:
// + - * / and unary -, sqrt, max (a < b ? b : a), nonNegative (x < 0 ? 0 : x)
// and squaredNorm. IEEE sums, products, quotients and square roots round the
// same in a lane as in a scalar register, and no multiply-add is fused
// (-ffp-contract=off): both give the same bits
// (tests/collision/test_pair_lanes.cpp).

/// MODEL §3.1 for one contact: the normal force F_n (N), its spring's energy (J)
/// and the power of its non-elastic part (W, dissipated).
template <class S>
struct NormalLoadOf {
  S force, potential, dissipation;
};

/// F_n = -κ_c d - μ_c ḋ clamped at >= 0 (a damper that would pull is clamped);
/// ½ κ_c d²; (F_n + κ_c d) ḋ, the damper's power or the clamp's.
template <class S>
NormalLoadOf<S> normalLaw(S stiffness, S damping, S depth, S depthRate) {
  const S force = nonNegative(-stiffness * depth - damping * depthRate);
  return {force, 0.5 * stiffness * depth * depth, (force + stiffness * depth) * depthRate};
}

/// MODEL §3.3: the anchor's damping c_t = ratio × 2 √(k_t m_eff) (N·s/m), from
/// k_t and the contact point's inverse effective mass 1/m_eff.
template <class S>
S tangentialDamping(S ratio, S tangentialStiffness, S inverseMass) {
  return ratio * 2.0 * sqrt(tangentialStiffness / inverseMass);
}

/// MODEL §3.7: what one contact adds to its particles' stability sums, the
/// larger of its normal and tangential stiffness (N/m) and damping (N·s/m), the
/// tangential ones scaled to the particles' mass by `rotation`, (1/m_eff) / (1/m)
/// (> 1 where the contact point also turns). (A contact between fixed sides adds
/// nothing: its callers' test.)
/// A particle's stability sums are Rates too: Σ of its contacts' rates, each
/// contact's added by `add` (with the share of it the particle carries), the
/// one place they are summed.
template <class S>
struct RatesOf {
  S stiffness = 0.0, damping = 0.0;
  void add(const RatesOf& rates, double share = 1.0) {
    stiffness += rates.stiffness * share;
    damping += rates.damping * share;
  }
};
template <class S>
RatesOf<S> stabilityRates(S stiffness, S damping, S tangentialStiffness, S tangentialDamping,
                          S rotation) {
  return {max(stiffness, tangentialStiffness * rotation),
          max(damping, tangentialDamping * rotation)};
}

/// MODEL §3.3, a contact's friction trial: the anchor spring's load -k_t δ_t
/// and the damper's -c_t v_t (v_t the slip), before its group decides.
template <class V>
struct AnchorLoadsOf {
  V elastic, damper;
};
template <class S, class V>
AnchorLoadsOf<V> anchorLoads(const V& delta, const V& slip, S tangentialStiffness,
                             S tangentialDamping) {
  return {delta * -tangentialStiffness, slip * -tangentialDamping};
}

/// What either friction law gives a contact: its new anchor (m), the friction
/// force on a (N), the anchor spring's energy (J) and the power dissipated (W).
template <class S, class V>
struct FrictionLoadOf {
  V anchor, force;
  S anchorEnergy, dissipated;
};

/// MODEL §3.3, friction that holds: sticking (scale 1) or breaking away (scale
/// μ_s Σ F_n / Σ|F_t| < 1, the group's). The anchor gives way to scale × δ_t
/// (anchor = relative - scale δ_t); the force is scale × (the anchor spring's and
/// damper's load); the anchor keeps ½ k_t |scale δ_t|²; the damper dissipates
/// scale c_t |v_t|².
template <class S, class V>
FrictionLoadOf<S, V> heldFriction(const V& relative, const V& delta, const V& tangentialLoad,
                                  S scale, S tangentialStiffness, S tangentialDamping,
                                  S slipSpeed) {
  const V held = delta * scale;
  return {relative - held, tangentialLoad * scale, 0.5 * tangentialStiffness * squaredNorm(held),
          scale * tangentialDamping * slipSpeed * slipSpeed};
}

/// MODEL §3.3, the coefficient of a contact sliding at |V| = `slipSpeed`:
/// μ_k + (μ_s - μ_k) exp(-(|V|/v_S)²) (Stribeck), continuous with breaking away
/// (μ_s) at the start of a slip and μ_k once the slip is fast against v_S; μ_k
/// at every speed when v_S = 0. (Scalar only: the lanes take no sliding
/// contact.)
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
template <class S, class V>
FrictionLoadOf<S, V> slidingFriction(const V& relative, const V& direction, S coefficient,
                                     S normalForce, S tangentialStiffness, S slipSpeed) {
  const S friction = coefficient * normalForce;
  const V consistent = direction * (friction / tangentialStiffness);
  return {relative - consistent, direction * -friction,
          0.5 * tangentialStiffness * squaredNorm(consistent), friction * slipSpeed};
}
