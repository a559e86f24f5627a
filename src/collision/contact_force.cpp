// The contact force (MODEL §3.1) and Coulomb friction (§3.3), realised for an
// explicit integrator with a tangential anchor spring (docs/contact.md):
//   sticking: F_t = -k_t δ_t - c_t v_t while |F_t| <= μ_s F_n (no creep: δ_t is a
//             displacement from a fixed anchor, so it cannot grow without bound);
//   sliding:  F_t = -μ_k F_n v̂_t, the anchor following at |δ_t| = μ_k F_n / k_t;
//   a sliding contact sticks again when |v_t| <= stickVelocity (the tolerance
//   that "V ≠ 0" needs in floating point).
#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/contact_stage.h"
#include "collision/facets.h"
#include "robophi/stability.h"

namespace robophi {

namespace {

struct StageTally {
  double potential = 0.0;
  double dissipativePower = 0.0;
  double releasedEnergy = 0.0;  // anchor energy lost when slipping or opening (J)
};

// One contact: normal force, friction, energy. `previous` is the same contact at
// the last evaluation, or nullptr for a new one. Returns the force on a.
inline Vec3 contactForce(const Model& model, const PairParameters& k, double reducedMass,
                         const Vec3& relative, const Vec3& relativeVelocity,
                         const Contact* previous, Contact& c, StageTally& tally) {
  const Vec3& n = c.normal;
  // MODEL §3.1: F = (-κ_c d - μ_c ḋ) k̂ for d < 0, clamped at >= 0.
  const double d = c.depth;
  const double dDot = dot(relativeVelocity, n);
  double normalForce = -k.stiffness * d - k.damping * dDot;
  if (normalForce < 0.0) normalForce = 0.0;
  c.normalForce = normalForce;
  tally.potential += 0.5 * k.stiffness * d * d;
  // Power of the non-elastic part: (F_n + κ d) ḋ (the damper, or the clamp).
  tally.dissipativePower += (normalForce + k.stiffness * d) * dDot;
  Vec3 force = n * normalForce;

  if (k.tangentialStiffness <= 0.0 || (k.staticFriction <= 0.0 && k.kineticFriction <= 0.0)) {
    c.anchor = relative;
    return force;
  }
  // MODEL §3.3 with an anchor: δ_t is the tangential part of the displacement
  // from where the contact stuck.
  double previousEnergy = 0.0;
  if (previous != nullptr) {
    c.anchor = previous->anchor;
    c.sliding = previous->sliding;
    previousEnergy = previous->anchorEnergy;
  } else {
    c.anchor = relative;
    c.sliding = 0;
  }
  const Vec3 displacement = relative - c.anchor;
  const Vec3 delta = displacement - n * dot(displacement, n);
  const Vec3 slip = relativeVelocity - n * dDot;
  const double tangentialDamping =
      k.tangentialDampingRatio * 2.0 * std::sqrt(k.tangentialStiffness * reducedMass);
  // The Coulomb test is on each part: the anchor spring (the load the contact
  // holds) and the damper (which acts only while the anchor moves) must each stay
  // within μ_s F_n, so |F_t| <= 2 μ_s F_n during a transient and μ_s F_n at rest.
  // A test on their sum would break a critically damped anchor loaded suddenly at
  // 88% of μ_s F_n: its sum overshoots the load by up to e^-2 = 13.5%.
  const Vec3 elastic = delta * -k.tangentialStiffness;
  const Vec3 damper = slip * -tangentialDamping;
  const double limit = k.staticFriction * normalForce;
  const double elasticSquared = squaredNorm(elastic);
  const double slipSquared = squaredNorm(slip);
  const double stickVelocity = model.contact.stickVelocity;
  // A sliding contact sticks again when its slip has fallen below the stick
  // velocity, or has reversed since the last evaluation: kinetic friction would
  // have stopped it within the step (without this, μ_k F_n flips the slip back
  // and forth every step, a chatter that never comes to rest).
  c.slip = slip;
  const bool reversed = previous != nullptr && dot(slip, previous->slip) < 0.0;
  const bool stick = elasticSquared <= limit * limit &&
                     (squaredNorm(damper) <= limit * limit || (c.sliding != 0 && reversed)) &&
                     (c.sliding == 0 || slipSquared <= stickVelocity * stickVelocity || reversed);
  if (stick) {
    // Sticking: friction cancels the tangential load (MODEL §3.3 F_f = -F_t).
    c.sliding = 0;
    c.anchor = relative - delta;
    c.anchorEnergy = 0.5 * k.tangentialStiffness * squaredNorm(delta);
    tally.dissipativePower -= tangentialDamping * slipSquared;
    return force + elastic + damper;
  }
  // Sliding (or breaking away): μ_k F_n against the slip velocity.
  Vec3 direction;
  const double slipSpeed = std::sqrt(slipSquared);
  if (slipSpeed > 0.0) {
    direction = slip / slipSpeed;
  } else if (elasticSquared > 0.0) {
    direction = elastic / -std::sqrt(elasticSquared);
  }
  const double friction = k.kineticFriction * normalForce;
  const Vec3 consistent = direction * (friction / k.tangentialStiffness);
  c.sliding = 1;
  c.anchor = relative - consistent;
  c.anchorEnergy = 0.5 * k.tangentialStiffness * squaredNorm(consistent);
  tally.releasedEnergy += previousEnergy - c.anchorEnergy;
  tally.dissipativePower -= friction * slipSpeed;
  return force - direction * friction;
}

// Adds one contact's stiffness and damping (the larger of the normal and the
// tangential ones) to its particles' sums.
void addContactRates(const Model& model, const PairParameters& k, const Contact& c,
                     ContactScratch& cache) {
  const double inverseMass =
      model.inverseMass[c.a] + (c.other >= 0 ? model.inverseMass[c.other] : 0.0);
  if (inverseMass == 0.0) return;
  const double stiffness = std::max(k.stiffness, k.tangentialStiffness);
  const double tangentialDamping =
      k.tangentialDampingRatio * 2.0 * std::sqrt(k.tangentialStiffness / inverseMass);
  const double damping = std::max(k.damping, tangentialDamping);
  cache.contactStiffnessSum[c.a] += stiffness;
  cache.contactDampingSum[c.a] += damping;
  if (c.other >= 0) {
    cache.contactStiffnessSum[c.other] += stiffness;
    cache.contactDampingSum[c.other] += damping;
  }
}

// The largest stable explicit step (s) of the contacts, by Gershgorin per
// particle as for the connectors (estimateStability): ω² <= 2 Σk / m,
// 2ζω <= 2 Σc / m, δ < 2/ω (√(1+ζ²) - ζ). Zeroes the sums again.
double contactsCriticalStep(const Model& model, const std::vector<Contact>& contacts,
                            ContactScratch& cache) {
  double step = std::numeric_limits<double>::infinity();
  for (const Contact& c : contacts) {
    for (const std::int32_t i : {c.a, c.other}) {
      if (i < 0 || cache.contactStiffnessSum[i] == 0.0) continue;
      const double omega = std::sqrt(2.0 * cache.contactStiffnessSum[i] * model.inverseMass[i]);
      const double dampingRate = 2.0 * cache.contactDampingSum[i] * model.inverseMass[i];
      cache.contactStiffnessSum[i] = 0.0;
      cache.contactDampingSum[i] = 0.0;
      step = std::min(step, dampedCriticalStep(omega, dampingRate));
    }
  }
  return step;
}

}  // namespace

void accumulateContacts(const Model& model, const ContactTables& tables, std::int64_t revision,
                        const std::vector<Vec3>& p, const std::vector<Vec3>& v,
                        const std::vector<Contact>& previous, ContactScratch& scratch,
                        Evaluation& out) {
  if (!model.contact.enabled || model.particleCount() == 0) {
    out.contactCriticalStep = std::numeric_limits<double>::infinity();
    out.contacts.clear();
    out.energy.contact = 0.0;
    out.releasedAnchorEnergy = 0.0;
    out.contactStats = ContactStats{};
    return;
  }
  ContactScratch& cache = prepareContactScratch(model, tables, revision, p, scratch);
  detectContacts(model, p, cache);

  StageTally tally;
  const auto particles = static_cast<std::size_t>(model.particleCount());
  if (cache.contactStiffnessSum.size() != particles) {
    cache.contactStiffnessSum.assign(particles, 0.0);
    cache.contactDampingSum.assign(particles, 0.0);
  }
  std::size_t old = 0;
  std::vector<Vec3>& f = out.force;
  ContactStats& stats = cache.stats;
  PairParameters overrideParameters;
  for (Contact& c : cache.freshContacts) {
    // Carry the friction anchor of a contact that persists (both lists sorted).
    const Contact::Key key = c.key();
    while (old < previous.size() && previous[old].key() < key) {
      tally.releasedEnergy += previous[old].anchorEnergy;  // contact opened
      ++old;
    }
    const Contact* before =
        old < previous.size() && previous[old].key() == key ? &previous[old] : nullptr;
    if (before != nullptr) ++old;
    const PairParameters& k = pairParameters(model, tables, c.a, c.other, overrideParameters);
    const std::int32_t a = c.a;
    double smallerRadius = model.radius[a];
    if (c.involvesFacets()) {  // MODEL §3.8 flat faces (collision/facets.h): the same law
      smallerRadius =
          applyFacetContact(model, k.stiffness, p, v, before, cache, c, f,
                            [&](double m, const Vec3& x, const Vec3& xDot, const Contact* h) {
                              return contactForce(model, k, m, x, xDot, h, c, tally);
                            });
    } else if (c.other >= 0) {
      const std::int32_t b = c.other;
      // k̂ from b to a; d = |p_a - p_b| - (r_a + r_b).
      const Vec3 relative = p[a] - p[b];
      const double distance = norm(relative);
      c.normal = distance > 0.0 ? relative / distance : Vec3{0.0, 0.0, 1.0};
      c.depth = distance - (model.radius[a] + model.radius[b]);
      smallerRadius = std::min(smallerRadius, model.radius[b]);
      // Reduced mass m_a m_b / (m_a + m_b); a fixed particle counts as infinitely heavy.
      const double inverseSum = model.inverseMass[a] + model.inverseMass[b];
      const double reducedMass = 1.0 / inverseSum;
      const Vec3 force =
          contactForce(model, k, reducedMass, relative, v[a] - v[b], before, c, tally);
      f[a] += force;
      f[b] -= force;
      ++stats.particleContacts;
    } else {
      const Vec3 force = contactForce(model, k, model.mass[a], p[a], v[a], before, c, tally);
      f[a] += force;
      ++stats.environmentContacts;
    }
    tally.potential += c.anchorEnergy;  // ½ k_t |δ_t|² of the friction anchor
    addContactRates(model, k, c, cache);
    stats.maxPenetration = std::max(stats.maxPenetration, -c.depth);
    stats.maxPenetrationFraction = std::max(stats.maxPenetrationFraction, -c.depth / smallerRadius);
  }
  for (; old < previous.size(); ++old) tally.releasedEnergy += previous[old].anchorEnergy;
  std::swap(out.contacts, cache.freshContacts);

  const double viscousPower = accumulateViscosity(model, p, v, f, cache);
  out.energy.contact = tally.potential;
  out.contactCriticalStep = contactsCriticalStep(model, out.contacts, cache);
  out.dissipativePower += tally.dissipativePower + viscousPower;
  out.releasedAnchorEnergy = tally.releasedEnergy;
  out.contactStats = cache.stats;
}

double deepestPenetrationFraction(const Model& model, const std::vector<Contact>& contacts) {
  double deepest = 0.0;
  for (const Contact& c : contacts) {
    double r = model.radius[c.a];
    if (c.other >= 0) r = std::min(r, model.radius[c.other]);
    deepest = std::max(deepest, -c.depth / r);
  }
  return deepest;
}

}  // namespace robophi
