// The lean contact stage's contacts four at a time (pair_lanes.h). The laws
// are not written here: collision/contact_law.inl, the scalar stage's source,
// is included below for this file's Lane and V3 (four contacts' numbers and
// vectors), in a namespace of its own compiled for AVX2 (STYLE 21). What is
// left here is the scalar stage's walk around the laws (contact_force.cpp:
// ChunkWalk, pairGeometry, pairArms, turningOf, contactRates, joinGroup,
// frictionForce), operation by operation and in its order: IEEE sums,
// products, quotients and square roots round the same in a lane as in a
// scalar register, and no fused multiply-add is enabled here
// (-ffp-contract=off, AVX2 only); tests/collision/test_pair_lanes.cpp checks
// the same bits.
#include "collision/pair_lanes.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "robophi/vec3.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace robophi::detail {

namespace {

std::atomic<bool> allowed{true};

#if defined(__x86_64__) && defined(__GNUC__)

// Every function from here to runLanes is compiled for AVX2, the law's
// templates (contact_law.inl) included.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif

#define ROBOPHI_LANES __attribute__((target("avx2"), always_inline)) inline

using D = __m256d;

// Three lanes' vectors: x, y and z of four contacts.
struct V3 {
  D x, y, z;
};

ROBOPHI_LANES D load(const double* a) { return _mm256_load_pd(a); }
ROBOPHI_LANES V3 load3(const double* x, const double* y, const double* z) {
  return {load(x), load(y), load(z)};
}
ROBOPHI_LANES void store(double* out, D v) { _mm256_store_pd(out, v); }
ROBOPHI_LANES void store3(double* x, double* y, double* z, const V3& v) {
  store(x, v.x);
  store(y, v.y);
  store(z, v.z);
}
ROBOPHI_LANES D add(D a, D b) { return _mm256_add_pd(a, b); }
ROBOPHI_LANES D sub(D a, D b) { return _mm256_sub_pd(a, b); }
ROBOPHI_LANES D mul(D a, D b) { return _mm256_mul_pd(a, b); }
ROBOPHI_LANES D div(D a, D b) { return _mm256_div_pd(a, b); }
ROBOPHI_LANES D all(double s) { return _mm256_set1_pd(s); }
// -x, as the scalar code's unary minus (the sign bit flipped).
ROBOPHI_LANES D negate(D a) { return _mm256_xor_pd(a, _mm256_set1_pd(-0.0)); }
// `mask ? b : a` lane by lane (mask: all ones or all zeros).
ROBOPHI_LANES D select(D mask, D b, D a) { return _mm256_blendv_pd(a, b, mask); }
// std::max(a, b): a < b ? b : a.
ROBOPHI_LANES D maxOf(D a, D b) { return select(_mm256_cmp_pd(a, b, _CMP_LT_OQ), b, a); }

ROBOPHI_LANES V3 add3(const V3& a, const V3& b) { return {add(a.x, b.x), add(a.y, b.y), add(a.z, b.z)}; }
ROBOPHI_LANES V3 sub3(const V3& a, const V3& b) { return {sub(a.x, b.x), sub(a.y, b.y), sub(a.z, b.z)}; }
ROBOPHI_LANES V3 scale3(const V3& a, D s) { return {mul(a.x, s), mul(a.y, s), mul(a.z, s)}; }
ROBOPHI_LANES D dot3(const V3& a, const V3& b) {
  return add(add(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z));
}
ROBOPHI_LANES V3 cross3(const V3& a, const V3& b) {
  return {sub(mul(a.y, b.z), mul(a.z, b.y)), sub(mul(a.z, b.x), mul(a.x, b.z)),
          sub(mul(a.x, b.y), mul(a.y, b.x))};
}
ROBOPHI_LANES V3 select3(D mask, const V3& b, const V3& a) {
  return {select(mask, b.x, a.x), select(mask, b.y, a.y), select(mask, b.z, a.z)};
}
// The stage's tangentialPart: projected twice on the plane normal to n.
ROBOPHI_LANES V3 tangential3(const V3& x, const V3& n) {
  const V3 once = sub3(x, scale3(n, dot3(x, n)));
  return sub3(once, scale3(n, dot3(once, n)));
}

// Four contacts' numbers as one number type for the laws (contact_law.inl):
// its operations are the lanes' add, sub, mul, div, negate, sqrt and maxOf,
// and nonNegative (x < 0 ? 0 : x); a double is the same in every lane.
struct Lane {
  D v;
  ROBOPHI_LANES Lane(D lanes) : v(lanes) {}
  ROBOPHI_LANES Lane(double s) : v(all(s)) {}
};
ROBOPHI_LANES Lane operator+(Lane a, Lane b) { return add(a.v, b.v); }
ROBOPHI_LANES Lane operator-(Lane a, Lane b) { return sub(a.v, b.v); }
ROBOPHI_LANES Lane operator*(Lane a, Lane b) { return mul(a.v, b.v); }
ROBOPHI_LANES Lane operator/(Lane a, Lane b) { return div(a.v, b.v); }
ROBOPHI_LANES Lane operator-(Lane a) { return negate(a.v); }
ROBOPHI_LANES Lane sqrt(Lane a) { return _mm256_sqrt_pd(a.v); }
ROBOPHI_LANES Lane max(Lane a, Lane b) { return maxOf(a.v, b.v); }
ROBOPHI_LANES Lane nonNegative(Lane a) {
  const D zero = _mm256_setzero_pd();
  return select(_mm256_cmp_pd(a.v, zero, _CMP_LT_OQ), zero, a.v);
}
// And four contacts' vectors as the laws' vector type.
ROBOPHI_LANES V3 operator-(const V3& a, const V3& b) { return sub3(a, b); }
ROBOPHI_LANES V3 operator*(const V3& a, Lane s) { return scale3(a, s.v); }
ROBOPHI_LANES Lane squaredNorm(const V3& a) { return dot3(a, a); }

// The laws, from the scalar stage's source.
namespace lanes {
#include "collision/contact_law.inl"  // NOLINT(bugprone-suspicious-include)
}  // namespace lanes

// The geometry of lanes l..l+3. A pair (pairGeometry, pairArms): p_a - p_b, the
// normal (0, 0, 1 at no distance), the depth, the arms to the overlap's middle.
// The environment: p_a, the detection's normal and depth, a's arm to its surface.
struct LaneGeometry {
  V3 rel, n, armA, armB;
  D depth, armLengthA, armLengthB;
};
ROBOPHI_LANES LaneGeometry laneGeometry(PairLaneBatch& b, std::size_t l) {
  const D zero = _mm256_setzero_pd(), one = all(1.0), half = all(0.5);
  const V3 none{zero, zero, zero};
  LaneGeometry g;
  const D environment = _mm256_cmp_pd(load(b.environment + l), one, _CMP_EQ_OQ);
  g.rel = sub3(load3(b.pax + l, b.pay + l, b.paz + l), load3(b.pbx + l, b.pby + l, b.pbz + l));
  const D distance = _mm256_sqrt_pd(dot3(g.rel, g.rel));
  const D apart = _mm256_cmp_pd(distance, zero, _CMP_GT_OQ);
  const V3 pairNormal = select3(
      apart, V3{div(g.rel.x, distance), div(g.rel.y, distance), div(g.rel.z, distance)},
      V3{zero, zero, one});
  g.n = select3(environment, load3(b.foundx + l, b.foundy + l, b.foundz + l), pairNormal);
  const D ra = load(b.ra + l), rb = load(b.rb + l);
  g.depth = select(environment, load(b.foundDepth + l), sub(distance, add(ra, rb)));
  g.armA = scale3(g.n, select(environment, negate(ra), negate(add(ra, mul(half, g.depth)))));
  g.armB = select3(environment, none, scale3(g.n, add(rb, mul(half, g.depth))));
  g.armLengthA = _mm256_sqrt_pd(dot3(g.armA, g.armA));
  g.armLengthB = _mm256_sqrt_pd(dot3(g.armB, g.armB));
  store3(b.relx + l, b.rely + l, b.relz + l, g.rel);
  store3(b.nx + l, b.ny + l, b.nz + l, g.n);
  store(b.depth + l, g.depth);
  store3(b.armAx + l, b.armAy + l, b.armAz + l, g.armA);
  store3(b.armBx + l, b.armBy + l, b.armBz + l, g.armB);
  store(b.armLengthA + l, g.armLengthA);
  store(b.armLengthB + l, g.armLengthB);
  return g;
}

// MODEL §3.1: F = (-κ_c d - μ_c ḋ) k̂, clamped at >= 0; its spring's energy and
// the power of its non-elastic part. Returns F_n.
ROBOPHI_LANES D laneNormalLaw(PairLaneBatch& b, std::size_t l, const LaneGeometry& g,
                              const V3& relativeVelocity) {
  const D dDot = dot3(relativeVelocity, g.n);
  const auto normal =
      lanes::normalLaw(Lane{load(b.stiffness + l)}, Lane{load(b.damping + l)}, Lane{g.depth},
                       Lane{dDot});
  store(b.normalForce + l, normal.force.v);
  store(b.normalPotential + l, normal.potential.v);
  store(b.normalDissipation + l, normal.dissipation.v);
  store3(b.normalx + l, b.normaly + l, b.normalz + l, scale3(g.n, normal.force.v));
  return normal.force.v;
}

// turningOf: a side that spins on its own turns its contact point; the contact
// point's velocity, its inverse effective mass, c_t, and contactRates (0 when
// both sides are fixed). Returns the contact point's velocity; c_t into `damping`.
ROBOPHI_LANES V3 laneTurning(PairLaneBatch& b, std::size_t l, const LaneGeometry& g,
                             const V3& relativeVelocity, D& tangentialDamping) {
  const D zero = _mm256_setzero_pd(), one = all(1.0);
  const D inverseMass = add(load(b.ima + l), load(b.imb + l));
  const D spinsA = _mm256_cmp_pd(load(b.spinsA + l), one, _CMP_EQ_OQ);
  const D spinsB = _mm256_cmp_pd(load(b.spinsB + l), one, _CMP_EQ_OQ);
  const D armInverseA =
      select(spinsA, mul(mul(g.armLengthA, g.armLengthA), load(b.spinInverseA + l)), zero);
  const D armInverseB =
      select(spinsB, mul(mul(g.armLengthB, g.armLengthB), load(b.spinInverseB + l)), zero);
  const V3 omegaA = load3(b.wax + l, b.way + l, b.waz + l);
  const V3 omegaB = load3(b.wbx + l, b.wby + l, b.wbz + l);
  const V3 roll = sub3(cross3(omegaA, g.armA), cross3(omegaB, g.armB));
  store3(b.rollx + l, b.rolly + l, b.rollz + l, roll);
  const D tangentialInverse = add(add(inverseMass, armInverseA), armInverseB);
  store(b.tangentialInverse + l, tangentialInverse);
  const D kt = load(b.tangentialStiffness + l);
  tangentialDamping =
      lanes::tangentialDamping(Lane{load(b.tangentialDampingRatio + l)}, Lane{kt},
                               Lane{tangentialInverse})
          .v;
  store(b.tangentialDamping + l, tangentialDamping);
  const D rotation =
      select(_mm256_cmp_pd(inverseMass, zero, _CMP_GT_OQ), div(tangentialInverse, inverseMass), one);
  const D bothFixed = _mm256_cmp_pd(inverseMass, zero, _CMP_EQ_OQ);
  const auto rates =
      lanes::stabilityRates(Lane{load(b.stiffness + l)}, Lane{load(b.damping + l)}, Lane{kt},
                            Lane{tangentialDamping}, Lane{rotation});
  store(b.rateStiffness + l, select(bothFixed, zero, rates.stiffness.v));
  store(b.rateDamping + l, select(bothFixed, zero, rates.damping.v));
  return add3(relativeVelocity, roll);
}

// The friction trial: δ_t from the anchor (from p_a - p_b itself for a new
// contact), or the offset a sliding contact's spring holds; the slip; both
// tangential; the spring's and damper's loads. Returns δ_t; the load into
// `tangentialLoad`.
ROBOPHI_LANES V3 laneTrial(PairLaneBatch& b, std::size_t l, const LaneGeometry& g,
                           const V3& pointVelocity, D tangentialDamping, D normalForce,
                           V3& tangentialLoad) {
  const D one = all(1.0);
  const D hasBefore = _mm256_cmp_pd(load(b.hasBefore + l), one, _CMP_EQ_OQ);
  const D slidBefore = _mm256_cmp_pd(load(b.slidBefore + l), one, _CMP_EQ_OQ);
  const V3 anchor = select3(hasBefore, load3(b.anchorx + l, b.anchory + l, b.anchorz + l), g.rel);
  const V3 delta = tangential3(
      select3(slidBefore, load3(b.offsetx + l, b.offsety + l, b.offsetz + l), sub3(g.rel, anchor)),
      g.n);
  store3(b.deltax + l, b.deltay + l, b.deltaz + l, delta);
  const V3 slip = tangential3(pointVelocity, g.n);
  store3(b.slipx + l, b.slipy + l, b.slipz + l, slip);
  const D slipSpeed = _mm256_sqrt_pd(dot3(slip, slip));
  store(b.slipSpeed + l, slipSpeed);
  const auto loads = lanes::anchorLoads(delta, slip, Lane{load(b.tangentialStiffness + l)},
                                        Lane{tangentialDamping});
  store3(b.elasticx + l, b.elasticy + l, b.elasticz + l, loads.elastic);
  store3(b.damperx + l, b.dampery + l, b.damperz + l, loads.damper);
  store(b.frictionLoad + l, mul(load(b.staticFriction + l), normalForce));
  tangentialLoad = add3(loads.elastic, loads.damper);
  return delta;
}

// The group of one contact (joinGroup, decideGroup) sticks while it was not
// sliding and |F_t| <= μ_s F_n; then frictionForce sticking (s = 1) and
// contactFriction: the anchor, its energy, the damper's power, the loads.
ROBOPHI_LANES void laneSticking(PairLaneBatch& b, std::size_t l, const LaneGeometry& g,
                                const V3& delta, const V3& tangentialLoad, D tangentialDamping) {
  const D zero = _mm256_setzero_pd(), one = all(1.0);
  const V3 none{zero, zero, zero};
  const D slidBefore = _mm256_cmp_pd(load(b.slidBefore + l), one, _CMP_EQ_OQ);
  const D groupTotal = add(zero, _mm256_sqrt_pd(dot3(tangentialLoad, tangentialLoad)));
  const D holds = _mm256_andnot_pd(
      slidBefore, _mm256_cmp_pd(groupTotal, add(zero, load(b.frictionLoad + l)), _CMP_LE_OQ));
  const int sticks = _mm256_movemask_pd(holds);
  for (int k = 0; k < 4; ++k) b.sticks[l + static_cast<std::size_t>(k)] = ((sticks >> k) & 1) != 0;
  const auto held = lanes::heldFriction(g.rel, delta, tangentialLoad, Lane{one},
                                        Lane{load(b.tangentialStiffness + l)},
                                        Lane{tangentialDamping}, Lane{load(b.slipSpeed + l)});
  store3(b.newAnchorx + l, b.newAnchory + l, b.newAnchorz + l, held.anchor);
  store(b.anchorEnergy + l, held.anchorEnergy.v);
  store(b.dissipated + l, held.dissipated.v);
  const V3 friction = held.force;
  const V3 normal = load3(b.normalx + l, b.normaly + l, b.normalz + l);
  store3(b.frictionx + l, b.frictiony + l, b.frictionz + l, friction);
  store3(b.forcex + l, b.forcey + l, b.forcez + l, add3(normal, friction));
  // The moments of a spinning side: 0 + arm × F_t (on b: × -F_t).
  const D spinsA = _mm256_cmp_pd(load(b.spinsA + l), one, _CMP_EQ_OQ);
  const D spinsB = _mm256_cmp_pd(load(b.spinsB + l), one, _CMP_EQ_OQ);
  const V3 torqueA = select3(spinsA, add3(none, cross3(g.armA, friction)), none);
  const V3 torqueB = select3(spinsB, add3(none, cross3(g.armB, scale3(friction, all(-1.0)))), none);
  store3(b.torqueAx + l, b.torqueAy + l, b.torqueAz + l, torqueA);
  store3(b.torqueBx + l, b.torqueBy + l, b.torqueBz + l, torqueB);
}

__attribute__((target("avx2"))) void runLanes(PairLaneBatch& b, std::size_t count) {
  for (std::size_t l = 0; l < count; l += 4) {
    const LaneGeometry g = laneGeometry(b, l);
    const V3 relativeVelocity =
        sub3(load3(b.vax + l, b.vay + l, b.vaz + l), load3(b.vbx + l, b.vby + l, b.vbz + l));
    const D normalForce = laneNormalLaw(b, l, g, relativeVelocity);
    D tangentialDamping;
    const V3 pointVelocity = laneTurning(b, l, g, relativeVelocity, tangentialDamping);
    V3 tangentialLoad;
    const V3 delta = laneTrial(b, l, g, pointVelocity, tangentialDamping, normalForce, tangentialLoad);
    laneSticking(b, l, g, delta, tangentialLoad, tangentialDamping);
  }
}

#undef ROBOPHI_LANES

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

// (compiled for any x86-64: it runs first)
const bool kHaveAvx2 = [] {
  __builtin_cpu_init();  // (a static initialiser may run before libgcc's)
  return __builtin_cpu_supports("avx2") != 0;
}();

#endif

}  // namespace

bool pairLanesAvailable() {
#if defined(__x86_64__) && defined(__GNUC__)
  return kHaveAvx2 && allowed.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

void allowPairLanes(bool allow) { allowed.store(allow, std::memory_order_relaxed); }

void runPairLanes(PairLaneBatch& batch, std::size_t count) {
#if defined(__x86_64__) && defined(__GNUC__)
  runLanes(batch, count);
#else
  (void)batch;
  (void)count;
#endif
}

}  // namespace robophi::detail
