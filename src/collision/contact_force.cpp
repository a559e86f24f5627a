// The contact force (MODEL §3.1) and Coulomb friction (§3.3), realised for an
// explicit integrator with a tangential anchor spring at the contact point
// (docs/contact.md):
//   - the friction of the contacts between two bodies is decided for the pair of
//     bodies as a whole (a contact group): the group sticks while the loads its
//     anchors hold sum to no more than μ_s Σ F_n, whatever the share of each
//     contact, so a block on many contacts holds until its friction angle;
//   - sticking: F_t = -k_t δ_t - c_t V while Σ|F_t| <= μ_s Σ F_n;
//   - breaking away (the paper's intermediate regime): the load exceeds
//     μ_s Σ F_n, friction holds at μ_s Σ F_n, the anchors give way; a group
//     whose anchors give way past their elastic range with the slip still
//     growing slides;
//   - sliding: F_t = -μ_k F_n V̂ with the anchor following at |δ_t| = μ_k F_n / k_t;
//     a sliding group sticks again when every contact's slip is below the stick
//     velocity or has reversed since the last evaluation;
//   - rolling: V and δ_t are those of the contact points, which turn with a
//     spinning particle or with the particle's LS neighbourhood; the friction
//     force's moment about the particle centre spins the particle, or is carried
//     by the neighbourhood as a couple.
#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/contact_law.h"
#include "collision/contact_stage.h"
#include "collision/facets.h"
#include "collision/pair_lanes.h"
#include "core/parallel.h"
#include "robophi/stability.h"

// A lambda the compiler must inline (GCC and Clang; elsewhere a hint left out).
#if defined(__GNUC__)
#define ROBOPHI_ALWAYS_INLINE __attribute__((always_inline))
#else
#define ROBOPHI_ALWAYS_INLINE
#endif

namespace robophi {

namespace {

struct StageTally {
  double potential = 0.0;
  double dissipativePower = 0.0;
  double releasedEnergy = 0.0;  // anchor energy lost when slipping or opening (J)
};

using FrictionTrial = ContactScratch::FrictionTrial;
using FrictionApplication = ContactScratch::FrictionApplication;
using FrictionGroup = ContactScratch::FrictionGroup;

// Contact::sliding: the friction regime of MODEL §3.3.
constexpr std::int32_t kSticking = 0, kSliding = 1, kBreakingAway = 2;
// How far (in elastic ranges μ_s F_n / k_t) a group's anchors may give way while
// breaking away before it slides: a body set down suddenly on a slope 1° below
// its friction angle gives way about 5 ranges while its anchors' overshoot
// (and the lattice's own settling) dies down, then sticks.
constexpr double kPresliding = 10.0;
// A contact whose normal turned by more than about 25° since the last evaluation
// (cos 25° ≈ 0.9) jumped from one face of its item to another.
constexpr double kNormalTurn = 0.9;
// A group breaking away with its contacts slipping faster than kSlidingSpeed
// times the speed an anchor reaches within its elastic range (μ_s F_n /
// √(k_t m_eff)) slides: a body that lands or is launched with a slip (V ≠ 0).
constexpr double kSlidingSpeed = 2.0;

// A pair contact's load on its particles (the other side's first), and its
// stiffness and damping into their stability sums.
// (From values, not a ContactLoad just written: read back whole, its vectors
// stall on their stores.)
inline void scatterLoad(std::int32_t a, std::int32_t other, const Vec3& force, const Vec3& torqueA,
                        const Vec3& torqueB, const law::Rates& rates, std::vector<Vec3>& f,
                        std::vector<Vec3>& torque, ContactScratch& cache) {
  const auto i = static_cast<std::size_t>(a);
  if (other >= 0) {
    const auto b = static_cast<std::size_t>(other);
    f[b] -= force;
    torque[b] += torqueB;
    cache.contactRateSum[b].add(rates);
  }
  f[i] += force;
  torque[i] += torqueA;
  cache.contactRateSum[i].add(rates);
}
inline void scatterLoad(const ContactScratch::ContactLoad& load, std::vector<Vec3>& f,
                        std::vector<Vec3>& torque, ContactScratch& cache) {
  scatterLoad(load.a, load.other, load.force, load.torqueA, load.torqueB, load.rates, f, torque,
              cache);
}

// A lean contact's loads: recorded for the gather by particle (`record`), or
// added now in contact order (scatterLoad).
inline void deliverLoad(ContactScratch::ContactLoad* record, std::int32_t a, std::int32_t other,
                        const Vec3& force, const Vec3& torqueA, const Vec3& torqueB,
                        const law::Rates& rates, std::vector<Vec3>* f, std::vector<Vec3>* torque,
                        ContactScratch& cache) {
  if (record != nullptr) {
    *record = {force, torqueA, torqueB, rates, a, other, false};
  } else {
    scatterLoad(a, other, force, torqueA, torqueB, rates, *f, *torque, cache);
  }
}
inline void deliverLoad(const ContactScratch::ContactLoad& load,
                        ContactScratch::ContactLoad* record, std::vector<Vec3>* f,
                        std::vector<Vec3>* torque, ContactScratch& cache) {
  deliverLoad(record, load.a, load.other, load.force, load.torqueA, load.torqueB, load.rates, f,
              torque, cache);
}

// x's part in the plane normal to the unit n, projected twice: a displacement or
// a velocity is mostly normal when a contact sticks, and one projection leaves a
// normal residue of rounding that is not small against what is left.
inline Vec3 tangentialPart(const Vec3& x, const Vec3& n) {
  const Vec3 once = x - n * dot(x, n);
  return once - n * dot(once, n);
}

// I⁺ v for the packed symmetric matrix (xx, yy, zz, xy, xz, yz).
inline Vec3 symmetricTimes(const double* m, const Vec3& v) {
  return {m[0] * v.x + m[3] * v.y + m[4] * v.z, m[3] * v.x + m[1] * v.y + m[5] * v.z,
          m[4] * v.x + m[5] * v.y + m[2] * v.z};
}

// The pseudo-inverse of a symmetric 3×3 matrix by Jacobi rotations; eigenvalues
// below 1e-9 of the largest count as zero (a row of particles cannot turn about
// its own line). Returns the largest eigenvalue of the inverse.
double jacobiPseudoInverse(const double* packed, double* inverse) {
  double a[3][3] = {{packed[0], packed[3], packed[4]},
                    {packed[3], packed[1], packed[5]},
                    {packed[4], packed[5], packed[2]}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int sweep = 0; sweep < 12; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off <= 1e-30 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2])) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t =
            (theta >= 0.0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A ← A J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // A ← Jᵀ A
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  const double largest = std::max({a[0][0], a[1][1], a[2][2]});
  double inv[3] = {0.0, 0.0, 0.0};
  double largestInverse = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (a[k][k] > 1e-9 * largest) {
      inv[k] = 1.0 / a[k][k];
      largestInverse = std::max(largestInverse, inv[k]);
    }
  }
  const auto entry = [&](int r, int c) {
    return v[r][0] * inv[0] * v[c][0] + v[r][1] * inv[1] * v[c][1] + v[r][2] * inv[2] * v[c][2];
  };
  inverse[0] = entry(0, 0);
  inverse[1] = entry(1, 1);
  inverse[2] = entry(2, 2);
  inverse[3] = entry(0, 1);
  inverse[4] = entry(0, 2);
  inverse[5] = entry(1, 2);
  return largestInverse;
}

// Whether a symmetric 3×3 matrix (packed xx yy zz xy xz yz) has a smallest
// eigenvalue above `ratio` (< 1) times its largest, which is positive; its
// smallest eigenvalue into `smallest`. Both in closed form (the trigonometric
// solution of the characteristic cubic: λ = q + 2p cos(φ + 2πk/3), q = tr A / 3,
// p² = tr((A − q1)²) / 6, cos 3φ = det((A − q1)/p) / 2, φ in [0, π/3]). The
// largest, q + 2p cos φ, lies between q + p and q + 2p: its cosine is taken only
// when those bounds leave the test open (the same answer as with it).
inline bool smallestEigenvalueAbove(const double* m, double ratio, double& smallest) {
  const double q = (m[0] + m[1] + m[2]) / 3.0;
  const double dxx = m[0] - q, dyy = m[1] - q, dzz = m[2] - q;
  const double off = m[3] * m[3] + m[4] * m[4] + m[5] * m[5];
  const double p2 = dxx * dxx + dyy * dyy + dzz * dzz + 2.0 * off;
  if (!(p2 > 0.0)) {
    smallest = q;
    return q > 0.0 && q > ratio * q;
  }
  const double p = std::sqrt(p2 / 6.0);
  const double determinant = dxx * (dyy * dzz - m[5] * m[5]) - m[3] * (m[3] * dzz - m[5] * m[4]) +
                             m[4] * (m[3] * m[5] - dyy * m[4]);
  const double r = std::clamp(0.5 * determinant / (p * p * p), -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  smallest = q + 2.0 * p * std::cos(phi + 2.0 * M_PI / 3.0);
  // cos φ <= 1, and the rounded products and sums keep that order: above the
  // bound, above the largest (which is then at least `smallest` > 0).
  if (smallest > 0.0 && smallest > ratio * (q + 2.0 * p)) return true;
  // cos φ >= 1/2 (up to rounding, far inside the margin of a half).
  if (!(smallest > ratio * (q + 0.5 * p))) return false;
  const double largest = q + 2.0 * p * std::cos(phi);
  return largest > 0.0 && smallest > ratio * largest;
}

// The pseudo-inverse of a symmetric positive semi-definite 3×3 matrix (packed
// xx yy zz xy xz yz), eigenvalues below 1e-9 of the largest counting as zero (a
// row of particles cannot turn about its own line); returns the largest
// eigenvalue of the inverse. A well-conditioned matrix (smallest eigenvalue
// above 1e-6 of the largest: every LS neighbourhood that is not a line) is
// inverted by its cofactors, its eigenvalues in closed form; the others by
// Jacobi rotations.
double symmetricPseudoInverse(const double* packed, double* inverse) {
  double smallest = 0.0;
  if (!smallestEigenvalueAbove(packed, 1.0e-6, smallest))
    return jacobiPseudoInverse(packed, inverse);
  const double xx = packed[0], yy = packed[1], zz = packed[2];
  const double xy = packed[3], xz = packed[4], yz = packed[5];
  const double cxx = yy * zz - yz * yz, cxy = xz * yz - xy * zz, cxz = xy * yz - xz * yy;
  const double determinant = xx * cxx + xy * cxy + xz * cxz;
  if (!(determinant > 0.0)) return jacobiPseudoInverse(packed, inverse);
  const double scale = 1.0 / determinant;
  inverse[0] = cxx * scale;
  inverse[1] = (xx * zz - xz * xz) * scale;
  inverse[2] = (xx * yy - xy * xy) * scale;
  inverse[3] = cxy * scale;
  inverse[4] = cxz * scale;
  inverse[5] = (xy * xz - xx * yz) * scale;
  return 1.0 / smallest;
}

// One point's share of a least-squares rotation fit (MODEL §3.3): A += w (|d|² 1 −
// d dᵀ) (packed xx yy zz xy xz yz) and b += w d × Δv, so that A ω = b.
inline void addRotationFit(const Vec3& d, const Vec3& dv, double w, double* a, Vec3& b) {
  a[0] += w * (d.y * d.y + d.z * d.z);
  a[1] += w * (d.x * d.x + d.z * d.z);
  a[2] += w * (d.x * d.x + d.y * d.y);
  a[3] -= w * d.x * d.y;
  a[4] -= w * d.x * d.z;
  a[5] -= w * d.y * d.z;
  b += cross(d, dv * w);
}

// What turns the contact point of particle i (MODEL §3.3 rolling): its own spin
// (a particle no LS ties), or the rotation of its LS neighbourhood, the
// least-squares ω of Δv_j = ω × d_j over its neighbours j (d_j = p_j - p_i),
// weighted by their masses: A ω = Σ m_j d_j × Δv_j, A = Σ m_j (|d_j|² 1 - d_j d_jᵀ).
// For a rigid body it is the body's ω; a line of particles cannot turn about
// itself (A⁺ drops that axis).
struct Turning {
  Vec3 omega;
  double armInverseInertia = 0.0;  // r² × the largest eigenvalue of J⁻¹ or A⁺
  std::int32_t kind = 0;           // 0 none, 1 spin, 2 neighbourhood
};

// How particle i's contact point turns (Turning::kind): 0 not at all (rolling
// off, a fixed particle, one of an object that does not turn (a rope's:
// ContactRole::turns), or one with nothing to turn with), 1 with
// its own spin, 2 with its LS neighbourhood.
inline std::int32_t turningKind(const Model& model, const ContactTables& tables, std::int32_t i) {
  if (!model.contact.rolling || tables.movable[i] == 0 || tables.noTurning[i] != 0) return 0;
  // Its own spin: a free particle's, or a rigid tree's particle's, its body's (State::spin).
  if (tables.inverseSpinInertia[i] > 0.0 || tables.treeOf[i] >= 0) return 1;
  return tables.rollNeighbourStart[i] == tables.rollNeighbourStart[i + 1] ? 0 : 2;
}

// The least-squares rotation of particle i's LS neighbourhood: ω into `omega`,
// A⁺ into `inverse`; returns A⁺'s largest eigenvalue (0: it does not turn).
double neighbourhoodRotation(const Model& model, const ContactTables& tables,
                             const std::vector<Vec3>& p, const std::vector<Vec3>& v, std::int32_t i,
                             Vec3& omega, double* inverse) {
  double a[6] = {0, 0, 0, 0, 0, 0};
  Vec3 b;
  for (std::int32_t k = tables.rollNeighbourStart[i]; k < tables.rollNeighbourStart[i + 1]; ++k) {
    const std::int32_t j = tables.rollNeighbour[static_cast<std::size_t>(k)];
    if (model.inverseMass[j] == 0.0) continue;  // a fixed neighbour takes no couple
    const Vec3 d = p[j] - p[i];
    const double w = model.mass[j];
    addRotationFit(d, v[j] - v[i], w, a, b);
  }
  const double largest = symmetricPseudoInverse(a, inverse);
  omega = largest == 0.0 ? Vec3{} : symmetricTimes(inverse, b);
  return largest;
}

inline Turning turningOf(const Model& model, const ContactTables& tables,
                         const ContactScratch& cache, const std::vector<Vec3>& p,
                         const std::vector<Vec3>& v, const std::vector<Vec3>& spin, std::int32_t i,
                         double arm, double* inverse) {
  Turning t;
  const std::int32_t kind = turningKind(model, tables, i);
  if (kind == 0) return t;
  if (kind == 1) {
    t.kind = 1;
    if (static_cast<std::size_t>(i) < spin.size()) {
      // Component by component: a block copy of the Vec3 is stored whole and
      // read back in other pairs (a stalled store forward on every contact).
      const Vec3& omega = spin[static_cast<std::size_t>(i)];
      t.omega = Vec3{omega.x, omega.y, omega.z};
    }
    t.armInverseInertia = arm * arm * tables.inverseSpinInertia[i];
    return t;
  }
  // Taken once per evaluation for every particle of a contact (TurningCache).
  const std::int32_t slot = cache.turning.slot[static_cast<std::size_t>(i)];
  double largest = 0.0;
  if (slot >= 0) {
    const auto k = static_cast<std::size_t>(slot);
    largest = cache.turning.largest[k];
    std::copy_n(cache.turning.inverse.data() + 6 * k, 6, inverse);
    t.omega = cache.turning.omega[k];
  } else {
    largest = neighbourhoodRotation(model, tables, p, v, i, t.omega, inverse);
  }
  if (largest == 0.0) return Turning{};
  t.kind = 2;
  t.armInverseInertia = arm * arm * largest;
  return t;
}

// The moment τ about particle i's centre of a force acting at its contact point:
// to the particle's spin, or as a couple on its neighbourhood, f_j = m_j β × d_j
// with β = A⁺ τ and -Σ f_j on i (zero net force; moment A β = τ; power τ·ω).
inline void applyMoment(const Model& model, const ContactTables& tables, const std::vector<Vec3>& p,
                        std::int32_t kind, const double* inverse, std::int32_t i,
                        const Vec3& moment, std::vector<Vec3>& f, std::vector<Vec3>& torque) {
  if (kind == 1) {
    torque[i] += moment;
  } else if (kind == 2) {
    const Vec3 beta = symmetricTimes(inverse, moment);
    Vec3 sum;
    for (std::int32_t k = tables.rollNeighbourStart[i]; k < tables.rollNeighbourStart[i + 1]; ++k) {
      const std::int32_t j = tables.rollNeighbour[static_cast<std::size_t>(k)];
      if (model.inverseMass[j] == 0.0) continue;
      const Vec3 force = cross(beta, p[j] - p[i]) * model.mass[j];
      f[j] += force;
      sum += force;
    }
    f[i] -= sum;
  }
}

// MODEL §3.1 round rims: a ring meets the environment as a rigid circle about
// the mass centre c of its particles, of radius R = mean |p_k - c|, turning
// with ω = A⁻¹ Σ m_k r_k × (v_k - v_c), A = Σ m_k (|r_k|² 1 - r_k r_kᵀ),
// r_k = p_k - c. A force F at the contact point (arm from c) reaches the
// particles as F m_k / M plus the couple f_k = m_k (A⁻¹ (arm × F)) × r_k (zero
// net force), and a radial load S ∂R/∂p_k: their power is F·(v_c + ω × arm) +
// S Ṙ, the rate of the contact's own variables, so the contact's energy account
// holds exactly for any motion of the ring that keeps its shape (and its size).
RingMotion ringMotion(const Model& model, const std::vector<Vec3>& p, const std::vector<Vec3>& v,
                      const RimRing& rim) {
  RingMotion ring;
  for (std::int32_t k = 0; k < rim.count; ++k) {
    const std::int32_t j = rim.first + k;
    ring.center += p[j] * model.mass[j];
    ring.velocity += v[j] * model.mass[j];
    ring.mass += model.mass[j];
  }
  ring.center = ring.center / ring.mass;
  ring.velocity = ring.velocity / ring.mass;
  double a[6] = {0, 0, 0, 0, 0, 0};
  Vec3 b;
  for (std::int32_t k = 0; k < rim.count; ++k) {
    const std::int32_t j = rim.first + k;
    const Vec3 d = p[j] - ring.center;
    const Vec3 dv = v[j] - ring.velocity;
    const double w = model.mass[j];
    const double length = norm(d);
    ring.radius += length;
    if (length > 0.0) {
      ring.radialSum += d / length;
      ring.radiusRate += dot(d, dv) / length;
    }
    addRotationFit(d, dv, w, a, b);
  }
  ring.radius /= rim.count;
  ring.radiusRate /= rim.count;
  ring.largestInverse = symmetricPseudoInverse(a, ring.inverse);
  ring.omega = symmetricTimes(ring.inverse, b);
  return ring;
}

// Adds `force` (N) at the contact point, the `moment` (N·m) about the ring's
// centre, and the radial load `squeeze` (N: S in S ∂R/∂p_k) to the ring's particles.
// A ring whose particles a rigid tree's body carries (a rigid URDF's wheel) takes
// the load as that body does, with the same force and moment about its centre: the
// force and the moment at its first particle, which the tree's gather adds to the
// body's wrench, rather than spread over all its particles (a rigid ring's radius
// does not change: no radial load).
void applyRingLoad(const Model& model, const ContactTables& tables, const std::vector<Vec3>& p,
                   const RimRing& rim, const RingMotion& ring, const Vec3& force,
                   const Vec3& moment, double squeeze, std::vector<Vec3>& f,
                   std::vector<Vec3>& torque) {
  if (tables.treeBodyOf[static_cast<std::size_t>(rim.first)] >= 0) {
    f[rim.first] += force;
    torque[rim.first] += moment + cross(ring.center - p[rim.first], force);
    return;
  }
  const Vec3 beta = symmetricTimes(ring.inverse, moment);
  const double n = static_cast<double>(rim.count);
  for (std::int32_t k = 0; k < rim.count; ++k) {
    const std::int32_t j = rim.first + k;
    const Vec3 d = p[j] - ring.center;
    const double length = norm(d);
    const double share = model.mass[j] / ring.mass;
    // ∂R/∂p_j = (r̂_j - (m_j / M) Σ r̂_k) / N.
    const Vec3 radial = ((length > 0.0 ? d / length : Vec3{}) - ring.radialSum * share) / n;
    f[j] += force * share + cross(beta, d) * model.mass[j] + radial * squeeze;
  }
}

// The radius (m) of a's surface at a contact, which rolls and whose fraction a
// depth is: a ball's sphere, else particle a's (a rim's tube).
inline double surfaceRadius(const Model& model, const Contact& c) {
  if (c.rim >= 0) {
    const RimRing& round = model.rims[static_cast<std::size_t>(c.rim)];
    if (round.isSphere()) return round.sphereRadius;
  }
  return model.radius[c.a];
}

// The contact group of a contact: the pair (object of a, object of the other
// particle or the environment item). Particles outside objects, and those whose
// friction decides alone (ContactTables::frictionAlone: a rope's), are their own.
inline std::int64_t groupKey(const ContactTables& tables, std::int32_t particle) {
  const std::int32_t object = tables.particleObject[particle];
  return object >= 0 && tables.frictionAlone[particle] == 0 ? object
                                                            : (std::int64_t{1} << 40) + particle;
}

// The stability rates of one contact (the larger of the normal and the
// tangential stiffness and damping, the tangential ones for the contact point's
// effective mass: rotationFactor), 0 when both its sides are fixed.
inline law::Rates contactRates(const ContactTables& tables, const PairParameters& k, std::int32_t a,
                               std::int32_t other, double rotationFactor,
                               double tangentialDamping) {
  const std::vector<double>& w = tables.contactInverseMass;
  const double inverseMass = w[a] + (other >= 0 ? w[other] : 0.0);
  if (inverseMass == 0.0) return {};
  return law::stabilityRates(k.stiffness, k.damping, k.tangentialStiffness, tangentialDamping,
                             rotationFactor);
}

// Adds a deferred contact's rates to its particles' sums: a rim's contact acts
// on the ring's mass M, each particle j taking m_j / M of it (Gershgorin row of
// F m_j / M).
void addDeferredRates(const Model& model, const Contact& c, const FrictionApplication& application,
                      ContactScratch& cache) {
  std::vector<law::Rates>& sums = cache.contactRateSum;
  if (application.facetStiffness > 0.0) sums[c.a].add({application.facetStiffness, 0.0});
  const law::Rates& rates = application.rates;
  if (rates.stiffness == 0.0 && rates.damping == 0.0) return;
  if (c.rim >= 0) {
    const RimRing& rim = model.rims[static_cast<std::size_t>(c.rim)];
    double mass = 0.0;
    for (std::int32_t j = rim.first; j < rim.first + rim.count; ++j) mass += model.mass[j];
    for (std::int32_t j = rim.first; j < rim.first + rim.count; ++j)
      sums[j].add(rates, model.mass[j] / mass);
    return;
  }
  sums[c.a].add(rates);
  if (c.facet >= 0) {  // (the touched side is the triangle's particles)
    addTriangleRates(model, c, rates, sums);
  } else if (c.other >= 0) {
    sums[c.other].add(rates);
  }
}

// Asks for the cache lines of the contact at `c` (a hint: no access, never
// faults).
inline void prefetchContact(const Contact* c, bool forWriting) {
#if defined(__GNUC__)
  const char* bytes = reinterpret_cast<const char*>(c);
  for (std::size_t offset = 0; offset < sizeof(Contact); offset += 64) {
    if (forWriting) {
      __builtin_prefetch(bytes + offset, 1);
    } else {
      __builtin_prefetch(bytes + offset, 0);
    }
  }
#else
  (void)c;
  (void)forWriting;
#endif
}

// Asks for the cache line at `x` (a hint).
inline void prefetchRead(const void* x) {
#if defined(__GNUC__)
  __builtin_prefetch(x, 0);
#else
  (void)x;
#endif
}

// What the friction of one contact adds to the stage's sums: the anchor energy
// it releases (J; -0 when none, so that adding it changes nothing) and the
// power it dissipates (W, >= 0, subtracted).
struct FrictionTerms {
  double released = -0.0;
  double dissipated = 0.0;
};

// The pair's friction parameters a contact's trial reads (k_t, μ_k, μ_s, v_S).
inline void takeFrictionParameters(FrictionTrial& t, const PairParameters& k) {
  t.tangentialStiffness = k.tangentialStiffness;
  t.kineticFriction = k.kineticFriction;
  t.staticFriction = k.staticFriction;
  t.stribeckVelocity = k.stribeckVelocity;
}

// Friction of one contact once its group has decided (MODEL §3.3's laws:
// law::heldFriction, law::slidingFriction). Returns F_t on a.
inline Vec3 frictionForce(const FrictionTrial& t, const FrictionGroup& g, Contact& c,
                          FrictionTerms& terms) {
  const double stiffness = t.tangentialStiffness;
  if (g.regime != kSliding) {
    // Sticking: friction cancels the tangential load (MODEL §3.3 F_f = -F_t).
    // Breaking away: the load is above μ_s Σ F_n; friction holds at μ_s Σ F_n
    // (every contact's spring and damper scaled by s = μ_s Σ F_n / Σ|F_t|) and
    // the anchors give way to s δ_t, their energy released.
    const double s = g.regime == kBreakingAway ? g.scale : 1.0;
    c.sliding = g.regime;
    c.giveWay = g.regime == kBreakingAway ? t.giveWayBefore + norm(t.delta) * (1.0 - s) : 0.0;
    const auto held = law::heldFriction(t.relative, t.delta, t.elastic + t.damper, s, stiffness,
                                        t.tangentialDamping, t.slipSpeed);
    c.anchor = held.anchor;
    c.anchorEnergy = held.anchorEnergy;
    if (s != 1.0) terms.released = 0.5 * stiffness * squaredNorm(t.delta) - c.anchorEnergy;
    terms.dissipated = held.dissipated;
    return held.force;
  }
  // Sliding: μ(|V|) F_n against the slip (against the held load if it has
  // stopped); μ from μ_s at the start of a slip to μ_k (law::slidingCoefficient).
  Vec3 direction;
  if (t.slipSpeed > 0.0) {
    direction = c.slip / t.slipSpeed;
  } else if (squaredNorm(t.elastic) > 0.0) {
    direction = t.elastic / -norm(t.elastic);
  }
  const double coefficient =
      law::slidingCoefficient(t.staticFriction, t.kineticFriction, t.slipSpeed, t.stribeckVelocity);
  const auto sliding = law::slidingFriction(t.relative, direction, coefficient, c.normalForce,
                                            stiffness, t.slipSpeed);
  c.sliding = kSliding;
  c.giveWay = 0.0;
  c.anchor = sliding.anchor;
  c.anchorEnergy = sliding.anchorEnergy;
  // The spring's energy at δ_t (what its work over the last step left there)
  // less what the sliding anchor keeps.
  terms.released = 0.5 * stiffness * squaredNorm(t.delta) - c.anchorEnergy;
  terms.dissipated = sliding.dissipated;
  return sliding.force;
}

// MODEL §3.3 rolling resistance: a torque μ_r F_n r against the relative
// rolling (ω_a - ω_b) about the tangent plane, r the particle's radius (a
// resistance μ_r F_n at the rim of a ball); linear below a rolling speed ω r of
// 1 mm/s. Returns the moment on a.
Vec3 rollingResistanceMoment(const PairParameters& k, const Contact& c, const Vec3& omegaA,
                             const Vec3& omegaB, double radius, StageTally& tally) {
  Vec3 rolling = omegaA - omegaB;
  rolling -= c.normal * dot(rolling, c.normal);
  const double speed = norm(rolling);
  if (speed == 0.0 || radius <= 0.0) return {};
  const double limit = k.rollingResistance * radius * c.normalForce;
  const double knee = 1e-3 / radius;  // rad/s
  const Vec3 moment = rolling * (-limit / std::max(speed, knee));
  tally.dissipativePower += dot(moment, rolling);
  return moment;
}

// The groups decide (MODEL §3.3's three regimes for the body as a whole):
// - sticking while the anchors' springs and dampers hold Σ|F_t| <= μ_s Σ F_n;
// - breaking away when Σ|F_t| exceeds it: friction saturates at μ_s Σ F_n;
//   a transient (a body set down on a slope, whose critically damped anchors
//   overshoot their load by up to e^-2) slows down under it and sticks again;
// - sliding once, while breaking away, the contacts slip faster than an
//   anchor moves within its elastic range (V ≠ 0: a body that lands or is
//   launched sliding), or the anchors have given way by more than kPresliding
//   elastic ranges μ_s F_n / k_t and the slip still grows (the load
//   is more than static friction can stop; a transient slows down under it):
//   μ_k F_n against the slip, until every contact has slowed below the stick
//   velocity or reversed.
// The sums over a group's contacts (in contact order) that only the decision of
// a group breaking away reads: Σ |V| at the last evaluation, the anchors'
// elastic range Σ μ_s F_n / k_t and Σ μ_s F_n / √(k_t m_eff).
void sumBreakingAway(const FrictionTrial* trials, std::size_t count, std::int32_t group,
                     FrictionGroup& g) {
  for (std::size_t k = 0; k < count; ++k) {
    const FrictionTrial& t = trials[k];
    if (t.group != group) continue;
    if (t.hadBefore) g.slipBefore += norm(t.slipBefore);
    g.range += t.frictionLoad / t.tangentialStiffness;
    g.elasticSpeed += t.frictionLoad * std::sqrt(t.tangentialInverse / t.tangentialStiffness);
  }
}

// Group `index` decides; `trials` holds the `count` contacts of its run.
inline void decideGroup(FrictionGroup& g, const FrictionTrial* trials, std::size_t count,
                        std::int32_t index) {
  g.scale = 1.0;
  if (g.wasSliding) {
    g.regime = g.allSlow && g.total <= g.normal ? kSticking : kSliding;
    return;
  }
  if (g.total > g.normal && g.wasBreakingAway) sumBreakingAway(trials, count, index, g);
  if (g.total <= g.normal) {
    g.regime = kSticking;
  } else if (g.wasBreakingAway && (g.slip > kSlidingSpeed * g.elasticSpeed ||
                                   (g.giveWay > kPresliding * g.range && g.slip > g.slipBefore))) {
    g.regime = kSliding;
  } else {
    g.regime = kBreakingAway;
    g.scale = g.normal / g.total;
  }
}

void decideGroups(std::vector<FrictionGroup>& groups, const FrictionTrial* trials,
                  std::size_t count) {
  for (std::size_t index = 0; index < groups.size(); ++index)
    decideGroup(groups[index], trials, count, static_cast<std::int32_t>(index));
}

// Adds a contact's trial to its group's sums (in contact order).
inline void joinGroup(FrictionGroup& group, const FrictionTrial& t) {
  group.normal += t.frictionLoad;  // the group's μ_s Σ F_n
  group.total += norm(t.elastic + t.damper);
  group.giveWay += t.giveWayBefore;
  group.slip += t.slipSpeed;
  // (slipBefore, range and elasticSpeed: sumBreakingAway, when needed.)
  group.wasSliding = group.wasSliding || t.regimeBefore == kSliding;
  group.wasBreakingAway = group.wasBreakingAway || t.regimeBefore == kBreakingAway;
  group.allSlow = group.allSlow && t.slow;
}

// A contact's friction once its group `g` has decided (none for a contact
// without friction: g null) into c, and onto its load unless it is deferred.
// Returns F_t on a.
inline Vec3 contactFriction(const FrictionTrial& t, const FrictionGroup* g, Contact& c,
                            ContactScratch::ContactLoad& load, FrictionTerms& terms) {
  Vec3 friction;
  if (g != nullptr) {
    friction = frictionForce(t, *g, c, terms);
  } else {
    c.sliding = 0;
  }
  c.frictionForce = friction;
  if (g != nullptr && !load.deferred) {
    load.force += friction;
    if (t.turnA == 1) load.torqueA += cross(t.armA, friction);
    if (t.turnB == 1) load.torqueB += cross(t.armB, friction * -1.0);
  }
  return friction;
}

// What the contact stage reads and writes, for its chunks: the contacts, loads
// and applications are written by index (each chunk its own), the rest read.
struct StageInput {
  const Model& model;
  const ContactTables& tables;
  const std::vector<Vec3>& p;
  const std::vector<Vec3>& v;
  const std::vector<Vec3>& spin;
  const std::vector<Contact>& previous;
  ContactScratch& cache;
  /// Set when the chunks run in order on one thread and no contact can be
  /// deferred (no facets, rims or particles turning with their LS
  /// neighbourhood): each contact's loads go to these as its run ends, in
  /// contact order, the order of the scatter they replace (the same bits).
  std::vector<Vec3>* force = nullptr;
  std::vector<Vec3>* torque = nullptr;
};

using ContactChunk = ContactScratch::ContactChunk;
using ContactLoad = ContactScratch::ContactLoad;

// A bare pair's contact (a, other) before the stage fills it in: the fields
// that are not the stage's are set here to their defaults (Contact{}); the
// stage sets the others on every path (a contact without friction its slip,
// give-way and, without rolling resistance, its roll velocity to zero). (A
// whole Contact{} is 224 bytes written twice over on every contact.)
inline void startBarePair(Contact& c, std::int32_t a, std::int32_t other) {
  c.a = a;
  c.other = other;
  c.rim = -1;
  c.arm = Vec3{};
  c.vertex = -1;
  c.facet = -1;
  c.facetWeights = Vec3{};
  c.edgeVertex = -1;
  c.edgeWeight = 0.0;
}

// A contact the detection found with its geometry (an environment, rim or
// facet contact, or a pair the trees found): its fields from the detection;
// the others, as a bare pair's, the stage sets (not copied, to be written over).
inline void startFoundContact(Contact& c, const Contact& found) {
  c.a = found.a;
  c.other = found.other;
  c.depth = found.depth;
  c.normal = found.normal;
  c.rim = found.rim;
  c.arm = found.arm;
  c.vertex = found.vertex;
  c.facet = found.facet;
  c.facetWeights = found.facetWeights;
  c.edgeVertex = found.edgeVertex;
  c.edgeWeight = found.edgeWeight;
}

// The contact point of a pair halfway through its overlap: the arms from a's
// and the other's centre for the normal k̂ (from the other to a) and depth d.
inline void pairArms(const Vec3& normal, double depth, double radiusA, double radiusB, Vec3& armA,
                     Vec3& armB) {
  armA = normal * -(radiusA + 0.5 * depth);
  armB = normal * (radiusB + 0.5 * depth);
}

// The geometry of a particle pair (a, b): p_a - p_b, the normal k̂ from b to a,
// d = |p_a - p_b| - (r_a + r_b), and the lengths of its arms (pairArms). (Its
// arms are worked out again from the normal and depth where they are needed:
// fewer stores and loads than keeping them.)
struct PairGeometry {
  Vec3 relative, normal;
  double depth = 0.0, armLengthA = 0.0, armLengthB = 0.0;
};

inline void pairGeometry(const Model& model, const std::vector<Vec3>& p, std::int32_t a,
                         std::int32_t b, PairGeometry& g) {
  g.relative = p[a] - p[b];
  const double distance = norm(g.relative);
  g.normal = distance > 0.0 ? g.relative / distance : Vec3{0.0, 0.0, 1.0};
  g.depth = distance - (model.radius[a] + model.radius[b]);
  Vec3 armA, armB;
  pairArms(g.normal, g.depth, model.radius[a], model.radius[b], armA, armB);
  g.armLengthA = norm(armA);
  g.armLengthB = norm(armB);
}

// A side's spin where its contact point turns with it (kind 1), else none.
inline Vec3 laneSpin(const std::vector<Vec3>& spin, std::int32_t i, std::int32_t kind) {
  return kind == 1 && static_cast<std::size_t>(i) < spin.size() ? spin[static_cast<std::size_t>(i)]
                                                                : Vec3{};
}

// Lane l's other side: a particle, or the environment (its side at rest, the
// detection's normal and depth).
void fillLaneOther(const StageInput& in, const ContactSeed& seed, std::int32_t kindB, std::size_t l,
                   detail::PairLaneBatch& b) {
  const std::int32_t other = seed.other();
  const bool environment = other < 0;
  Vec3 pb, vb, wb, foundNormal;
  double rb = 0.0, imb = 0.0, spinInverseB = 0.0, foundDepth = 0.0;
  if (environment) {
    const Contact& found = seed.full >= 0
                               ? in.cache.detectedContacts[static_cast<std::size_t>(seed.full)]
                               : in.cache.treeContacts[static_cast<std::size_t>(-2 - seed.full)];
    foundNormal = found.normal;
    foundDepth = found.depth;
  } else {
    pb = in.p[other];
    vb = in.v[other];
    wb = laneSpin(in.spin, other, kindB);
    rb = in.model.radius[other];
    imb = in.tables.contactInverseMass[other];
    spinInverseB = in.tables.inverseSpinInertia[other];
  }
  b.environment[l] = environment ? 1.0 : 0.0;
  b.foundx[l] = foundNormal.x, b.foundy[l] = foundNormal.y, b.foundz[l] = foundNormal.z;
  b.foundDepth[l] = foundDepth;
  b.pbx[l] = pb.x, b.pby[l] = pb.y, b.pbz[l] = pb.z;
  b.vbx[l] = vb.x, b.vby[l] = vb.y, b.vbz[l] = vb.z;
  b.wbx[l] = wb.x, b.wby[l] = wb.y, b.wbz[l] = wb.z;
  b.rb[l] = rb;
  b.imb[l] = imb;
  b.spinInverseB[l] = spinInverseB;
  b.spinsB[l] = kindB == 1 ? 1.0 : 0.0;
}

// Contact `seed`'s inputs into lane l (its record of the last evaluation:
// `before`), and whether the lanes work it out (`use`: it has friction and no
// rolling resistance, and each side spins or does not turn; the others, whose
// bare pairs take only their geometry from the lanes, the scalar stage works out).
void fillLane(const StageInput& in, const ContactSeed& seed, const Contact* before, std::size_t l,
              detail::PairLaneBatch& b, bool& use) {
  const Model& model = in.model;
  const ContactTables& tables = in.tables;
  const std::int32_t a = seed.a(), other = seed.other();
  PairParameters unused;  // (the lanes run only without overrides)
  const PairParameters& k = pairParameters(model, tables, a, other, unused);
  const std::int32_t kindA = turningKind(model, tables, a);
  const std::int32_t kindB = other < 0 ? 0 : turningKind(model, tables, other);
  use = k.tangentialStiffness > 0.0 && (k.staticFriction > 0.0 || k.kineticFriction > 0.0) &&
        !(k.rollingResistance > 0.0) && kindA != 2 && kindB != 2;
  const Vec3& pa = in.p[a];
  const Vec3& va = in.v[a];
  const Vec3 wa = laneSpin(in.spin, a, kindA);
  b.pax[l] = pa.x, b.pay[l] = pa.y, b.paz[l] = pa.z;
  b.vax[l] = va.x, b.vay[l] = va.y, b.vaz[l] = va.z;
  b.wax[l] = wa.x, b.way[l] = wa.y, b.waz[l] = wa.z;
  b.ra[l] = model.radius[a];
  b.ima[l] = tables.contactInverseMass[a];
  b.spinInverseA[l] = tables.inverseSpinInertia[a];
  b.spinsA[l] = kindA == 1 ? 1.0 : 0.0;
  fillLaneOther(in, seed, kindB, l, b);
  const Vec3 anchor = before != nullptr ? before->anchor : Vec3{};
  const bool slid = before != nullptr && before->sliding == kSliding;
  const Vec3 offset = slid ? before->frictionForce * (-1.0 / k.tangentialStiffness) : Vec3{};
  b.anchorx[l] = anchor.x, b.anchory[l] = anchor.y, b.anchorz[l] = anchor.z;
  b.hasBefore[l] = before != nullptr ? 1.0 : 0.0;
  b.offsetx[l] = offset.x, b.offsety[l] = offset.y, b.offsetz[l] = offset.z;
  b.slidBefore[l] = slid ? 1.0 : 0.0;
  b.stiffness[l] = k.stiffness;
  b.damping[l] = k.damping;
  b.tangentialStiffness[l] = k.tangentialStiffness;
  b.staticFriction[l] = k.staticFriction;
  b.tangentialDampingRatio[l] = k.tangentialDampingRatio;
}

// The lanes past a batch of `count` up to the next four: a copy of its first.
void padLanes(detail::PairLaneBatch& b, std::size_t count) {
  for (std::size_t l = count; l % 4 != 0; ++l) {
    // clang-format off
    for (double* x :
         {b.pax, b.pay, b.paz, b.pbx, b.pby, b.pbz, b.vax, b.vay, b.vaz, b.vbx, b.vby, b.vbz,
          b.wax, b.way, b.waz, b.wbx, b.wby, b.wbz, b.anchorx, b.anchory, b.anchorz, b.hasBefore,
          b.offsetx, b.offsety, b.offsetz, b.slidBefore, b.environment, b.foundx, b.foundy,
          b.foundz, b.foundDepth, b.ra, b.rb, b.ima, b.imb, b.spinInverseA, b.spinInverseB,
          b.spinsA, b.spinsB, b.stiffness, b.damping, b.tangentialStiffness, b.staticFriction,
          b.tangentialDampingRatio})
      // clang-format on
      x[l] = x[0];
  }
}

// The lean stage's batch [begin, end) into the lanes (pair_lanes.h): each
// contact's inputs (fillLane), where its history is (PairLaneBatch::history,
// persists), and the lanes past it padded (padLanes). `old` is the history's
// cursor at `begin`; the next batch's contacts and history are asked for ahead
// (the history and the new list are larger than the cache).
void fillPairLanes(const StageInput& in, std::size_t begin, std::size_t end, std::size_t old,
                   std::size_t oldEnd, detail::PairLaneBatch& b, bool* use) {
  const std::vector<Contact>& previous = in.previous;
  const ContactScratch& cache = in.cache;
  for (std::size_t j = begin; j < end; ++j) {
    const std::size_t l = j - begin;
    const ContactSeed& seed = cache.seeds[j];
    while (old < oldEnd && previous[old].key() < seed.key) ++old;
    const Contact* before =
        old < oldEnd && previous[old].key() == seed.key ? &previous[old] : nullptr;
    b.history[l] = old;
    b.persists[l] = before != nullptr;
    if (before != nullptr) ++old;
    fillLane(in, seed, before, l, b, use[l]);
  }
  const std::size_t next = std::min(cache.seeds.size(), end + detail::PairLaneBatch::kSize);
  for (std::size_t j = end; j < next; ++j) {
    prefetchContact(cache.freshContacts.data() + j, true);
    if (old + (j - end) < oldEnd) prefetchContact(previous.data() + old + (j - end), false);
    const std::int32_t other = cache.seeds[j].other();
    if (other >= 0) {
      prefetchRead(in.p.data() + other);
      prefetchRead(in.v.data() + other);
    }
  }
  padLanes(b, end - begin);
}

// A lean contact the lanes worked out (fillPairLanes, runPairLanes), its
// Contact started (startBarePair, startFoundContact): into the contact, the
// stage's sums and its particles' loads, as the scalar stage does from its
// normal force on. A contact that sticks takes the lanes' friction; the others'
// group decides here, by the scalar stage's code, from the lanes' trial. Its
// loads go to `record` (threads: the gather) or are added now (deliverLoad).
inline void addLaneContact(const detail::PairLaneBatch& b, std::size_t l, const StageInput& in,
                           std::int32_t a, std::int32_t other, const Contact* before, Contact& c,
                           FrictionTrial& t, ContactLoad& load, ContactLoad* record,
                           StageTally& tally, ContactStats& stats,
                           ContactChunk::RunTerms& runTerms) {
  const Model& model = in.model;
  ContactScratch& cache = in.cache;
  const double depth = b.depth[l];
  c.normal = {b.nx[l], b.ny[l], b.nz[l]};
  c.depth = depth;
  c.normalForce = b.normalForce[l];
  tally.potential += b.normalPotential[l];
  tally.dissipativePower += b.normalDissipation[l];
  stats.maxPenetration = std::max(stats.maxPenetration, -depth);
  const double smallerRadius =
      other >= 0 ? std::min(model.radius[a], model.radius[other]) : model.radius[a];
  if (-depth > stats.maxPenetrationFraction * smallerRadius * (1.0 - 1e-9))
    stats.maxPenetrationFraction = std::max(stats.maxPenetrationFraction, -depth / smallerRadius);
  if (other >= 0) {
    ++stats.particleContacts;
  } else {
    ++stats.environmentContacts;
  }
  c.rollVelocity = {b.rollx[l], b.rolly[l], b.rollz[l]};
  c.slip = {b.slipx[l], b.slipy[l], b.slipz[l]};
  if (b.sticks[l]) {
    c.sliding = kSticking;
    c.giveWay = 0.0;
    c.anchor = {b.newAnchorx[l], b.newAnchory[l], b.newAnchorz[l]};
    c.anchorEnergy = b.anchorEnergy[l];
    c.frictionForce = {b.frictionx[l], b.frictiony[l], b.frictionz[l]};
    runTerms = {-0.0, b.dissipated[l], b.anchorEnergy[l]};
    deliverLoad(record, a, other, {b.forcex[l], b.forcey[l], b.forcez[l]},
                {b.torqueAx[l], b.torqueAy[l], b.torqueAz[l]},
                {b.torqueBx[l], b.torqueBy[l], b.torqueBz[l]},
                {b.rateStiffness[l], b.rateDamping[l]}, in.force, in.torque, cache);
    return;
  }
  // The trial and the loads before friction (settle), as the scalar stage
  // leaves them.
  PairParameters unused;  // (the lanes run only without overrides)
  const PairParameters& k = pairParameters(model, in.tables, a, other, unused);
  t.turnA = b.spinsA[l] == 1.0 ? 1 : 0;
  t.turnB = b.spinsB[l] == 1.0 ? 1 : 0;
  t.ring = -1;
  t.relative = {b.relx[l], b.rely[l], b.relz[l]};
  t.armA = {b.armAx[l], b.armAy[l], b.armAz[l]};
  t.armB = {b.armBx[l], b.armBy[l], b.armBz[l]};
  takeFrictionParameters(t, k);
  t.tangentialDamping = b.tangentialDamping[l];
  load.a = a;
  load.other = other;
  load.deferred = false;
  load.force = {b.normalx[l], b.normaly[l], b.normalz[l]};
  load.torqueA = Vec3{};
  load.torqueB = Vec3{};
  load.rates = {b.rateStiffness[l], b.rateDamping[l]};
  t.previousEnergy = before != nullptr ? before->anchorEnergy : 0.0;
  t.regimeBefore = before != nullptr ? before->sliding : kSticking;
  t.giveWayBefore = before != nullptr ? before->giveWay : 0.0;
  t.delta = {b.deltax[l], b.deltay[l], b.deltaz[l]};
  if (t.regimeBefore == kSliding)
    tally.releasedEnergy += t.previousEnergy - 0.5 * k.tangentialStiffness * squaredNorm(t.delta);
  t.slipSpeed = b.slipSpeed[l];
  t.elastic = {b.elasticx[l], b.elasticy[l], b.elasticz[l]};
  t.damper = {b.damperx[l], b.dampery[l], b.damperz[l]};
  const bool reversed = before != nullptr && dot(c.slip, before->slip) < 0.0;
  t.slow = t.slipSpeed <= model.contact.stickVelocity || reversed;
  t.frictionLoad = b.frictionLoad[l];
  t.tangentialInverse = b.tangentialInverse[l];
  t.hadBefore = before != nullptr;
  if (t.hadBefore) t.slipBefore = before->slip;
  FrictionGroup group;
  t.group = 0;
  joinGroup(group, t);
  decideGroup(group, &t, 1, 0);
  FrictionTerms terms;
  contactFriction(t, &group, c, load, terms);
  deliverLoad(load, record, in.force, in.torque, cache);
  runTerms = {terms.released, terms.dissipated, c.anchorEnergy};
}

// One chunk of the contacts, walked in contact order by ChunkWalk::run. For
// each contact, these steps (each a named member below):
//   nextBatch      the bare pairs' geometry a batch ahead (AVX2 lanes or scalar);
//   startContact   the contact from what the detection found, and its record of
//                  the last evaluation (the friction history);
//   laneContact    (lean, AVX2) the whole contact the lanes worked out;
//   beginTrial     the pair's parameters, its run and its friction trial's slot;
//   sideGeometry   facet | particle pair | rim | environment: the touching
//                  point's relative position, velocity, arms and effective mass;
//   applyNormalLaw MODEL §3.1;
//   turnSides      how each side turns its contact point (MODEL §3.3 rolling);
//   frictionTrial  MODEL §3.3 with an anchor: δ_t, the slip, the spring and damper;
//   joinOrDecide   the contact joins its group (lean: decides at once);
//   finishRun      at a run's end (a's object's contacts) the groups decide and
//                  the friction forces follow.
// A contact between two particles, or one and the environment, whose sides spin
// or do not turn, leaves its loads for the gather by particle; the others
// (facets, rims, a side turning with its LS neighbourhood) are deferred to the
// serial pass.
// Lean: every group is one contact (ContactTables::singleParticleBodies) and
// none is deferred: each contact's group decides, and its friction and loads
// follow, as soon as its trial is taken, the same operations as at the end of
// its run; its loads are added at once (StageInput::force, one thread) or
// recorded for the gather by particle (ContactScratch::loads); the run's end
// adds what it left for the stage's sums (ContactChunk::runTerms), in the same
// order.
template <bool Lean>
class ChunkWalk {
 public:
  ChunkWalk(const StageInput& in, ContactChunk& chunk)
      : in_(in),
        model_(in.model),
        tables_(in.tables),
        p_(in.p),
        v_(in.v),
        previous_(in.previous),
        cache_(in.cache),
        contacts_(in.cache.freshContacts),
        chunk_(chunk),
        stickVelocity_(in.model.contact.stickVelocity),
        direct_(in.force != nullptr),
        runFirst_(chunk.begin),
        old_(chunk.historyBegin),
        oldEnd_(chunk.historyEnd),
        batchBegin_(chunk.begin),
        batchEnd_(chunk.begin),
        lanes_(Lean && in.tables.overrides.empty() && detail::pairLanesAvailable()) {
    chunk_.stats = ContactStats{};
    chunk_.groups.clear();
    chunk_.rings.clear();
    chunk_.inverses.clear();
    chunk_.deferred.clear();
  }

  void run() {
    for (std::size_t index = chunk_.begin; index < chunk_.end; ++index) contactAt(index);
    for (; old_ < oldEnd_; ++old_) tally_.releasedEnergy += previous_[old_].anchorEnergy;
    finishRun(chunk_.end);
    chunk_.potential = tally_.potential;
    chunk_.dissipativePower = tally_.dissipativePower;
    chunk_.releasedEnergy = tally_.releasedEnergy;
  }

 private:
  // The contact being worked out (set by startContact .. frictionTrial).
  struct Current {
    std::size_t index = 0;
    const ContactSeed* seed = nullptr;
    std::int32_t a = -1, other = -1;
    Contact* c = nullptr;
    const Contact* before = nullptr;  // its record of the last evaluation, if it persists
    const PairParameters* k = nullptr;
    bool frictionless = false, faceted = false, rimmed = false;
    FrictionTrial* t = nullptr;
    double smallerRadius = 0.0, inverseMass = 0.0;
    double squeezeRate = 0.0;                     // rims: n·u, ∂d/∂R
    double armLengthA = -1.0, armLengthB = -1.0;  // |arm|s of a batch-worked pair
    double facetStiffness = 0.0, normalForce = 0.0;
    Vec3 relativeVelocity, rollVelocity;  // of the centres; ω × arm's
    Vec3 normal, rollMoment;              // F_n k̂; the rolling resistance on a
    Turning ta, tb;
  };

  void contactAt(std::size_t index) ROBOPHI_ALWAYS_INLINE {
    // The lists are larger than the cache: fetch the contacts a few ahead (the
    // new one to write, the history's to read). (The lanes fetch a batch ahead:
    // fillPairLanes.)
    constexpr std::size_t kAhead = 6;
    if (!lanes_ && index + kAhead < chunk_.end)
      prefetchContact(contacts_.data() + index + kAhead, true);
    if (!lanes_ && old_ + kAhead < oldEnd_)
      prefetchContact(previous_.data() + old_ + kAhead, false);
    if (index == batchEnd_) nextBatch(index);
    startContact(index);
    if constexpr (Lean) {
      if (lanes_ && useLanes_[index - batchBegin_]) {
        laneContact();
        return;
      }
    }
    beginTrial();
    sideGeometry();
    applyNormalLaw();
    Current& w = w_;
    if (w.frictionless && w.k->rollingResistance <= 0.0) {
      w.c->rollVelocity = Vec3{};
      withoutAnchor();
      return;
    }
    turnSides();
    if (w.frictionless) {
      withoutAnchor();
      return;
    }
    frictionTrial();
    joinOrDecide();
  }

  // The geometry of the bare particle pairs (most contacts), worked out a batch
  // ahead: a pair's chain of square roots and divisions (distance, normal,
  // arms' lengths) is long, and the pairs of a batch overlap theirs, where
  // within the loop each waited for its own. Lean with AVX2: the batch's
  // contacts four at a time (pair_lanes.h), the geometry of each bare pair and
  // the whole of each contact the lanes work out (`useLanes_`).
  void nextBatch(std::size_t index) {
    batchBegin_ = index;
    batchEnd_ = std::min(chunk_.end, index + kBatch);
    if (!lanes_) {
      for (std::size_t j = batchBegin_; j < batchEnd_; ++j) {
        const ContactSeed& pair = cache_.seeds[j];
        if (pair.full == -1)
          pairGeometry(model_, p_, pair.a(), pair.other(), batch_[j - batchBegin_]);
      }
      return;
    }
    fillPairLanes(in_, batchBegin_, batchEnd_, old_, oldEnd_, laneBatch_, useLanes_);
    detail::runPairLanes(laneBatch_, batchEnd_ - batchBegin_);
    for (std::size_t j = batchBegin_; j < batchEnd_; ++j) {
      const std::size_t l = j - batchBegin_;
      if (useLanes_[l] || cache_.seeds[j].full != -1) continue;  // (only the scalar stage's)
      PairGeometry& g = batch_[l];
      g.relative = {laneBatch_.relx[l], laneBatch_.rely[l], laneBatch_.relz[l]};
      g.normal = {laneBatch_.nx[l], laneBatch_.ny[l], laneBatch_.nz[l]};
      g.depth = laneBatch_.depth[l];
      g.armLengthA = laneBatch_.armLengthA[l];
      g.armLengthB = laneBatch_.armLengthB[l];
    }
  }

  // The contact, built once from what the detection found (its key and sides
  // read from the seed: read back from c, they stall on its stores), and the
  // friction anchor of a contact that persists (both lists sorted): what opened
  // before this key is released, then its own record taken. (The lanes' batch
  // has walked the history already: fillPairLanes.)
  void startContact(std::size_t index) ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    w.index = index;
    w.seed = &cache_.seeds[index];
    const ContactSeed& seed = *w.seed;
    w.a = seed.a();
    w.other = seed.other();
    w.c = &contacts_[index];
    if (seed.full == -1) {
      startBarePair(*w.c, w.a, w.other);
    } else {
      startFoundContact(*w.c, seed.full >= 0
                                  ? cache_.detectedContacts[static_cast<std::size_t>(seed.full)]
                                  : cache_.treeContacts[static_cast<std::size_t>(-2 - seed.full)]);
    }
    w.before = nullptr;
    if (lanes_) {
      const std::size_t l = index - batchBegin_;
      for (; old_ < laneBatch_.history[l]; ++old_)
        tally_.releasedEnergy += previous_[old_].anchorEnergy;
      if (laneBatch_.persists[l]) w.before = &previous_[old_++];
      return;
    }
    while (old_ < oldEnd_ && previous_[old_].key() < seed.key) {
      tally_.releasedEnergy += previous_[old_].anchorEnergy;  // contact opened
      ++old_;
    }
    if (old_ < oldEnd_ && previous_[old_].key() == seed.key) w.before = &previous_[old_++];
  }

  // A contact the lanes worked out whole (lean): into its run and the sums.
  void laneContact() {
    Current& w = w_;
    const std::int64_t objectA = groupKey(tables_, w.a);
    if (objectA != runObject_) {  // (it has friction)
      finishRun(w.index);
      runObject_ = objectA;
    }
    const std::size_t slot = w.index - runFirst_;
    if (chunk_.runTerms.size() <= slot) chunk_.runTerms.resize(slot + 1);
    addLaneContact(laneBatch_, w.index - batchBegin_, in_, w.a, w.other, w.before, *w.c, leanTrial_,
                   leanLoad_, direct_ ? nullptr : &cache_.loads[w.index], tally_, chunk_.stats,
                   chunk_.runTerms[slot]);
  }

  // The pair's parameters; a contact with friction of another object than the
  // last one's ends the run (its groups decide); the trial's slot in the run.
  void beginTrial() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    const PairParameters& k = pairParameters(model_, tables_, w.a, w.other, overrideParameters_);
    w.k = &k;
    w.frictionless =
        k.tangentialStiffness <= 0.0 || (k.staticFriction <= 0.0 && k.kineticFriction <= 0.0);
    // The group: (a's object, the other's object or the environment item).
    const std::int64_t objectA = groupKey(tables_, w.a);
    if (!w.frictionless && objectA != runObject_) {
      finishRun(w.index);
      runObject_ = objectA;
    }
    const std::size_t slot = w.index - runFirst_;
    w.t = &leanTrial_;
    if constexpr (Lean) {
      if (chunk_.runTerms.size() <= slot) chunk_.runTerms.resize(slot + 1);
    } else {
      if (chunk_.trials.size() <= slot) chunk_.trials.resize(slot + 1);
      if (direct_ && chunk_.runLoads.size() <= slot) chunk_.runLoads.resize(slot + 1);
      w.t = &chunk_.trials[slot];
    }
    FrictionTrial& t = *w.t;
    t.turnA = 0;
    t.turnB = 0;
    t.ring = -1;
    w.smallerRadius = model_.radius[w.a];
    w.relativeVelocity = Vec3{};
    w.inverseMass = tables_.contactInverseMass[w.a];
    // MODEL §3.8 flat faces (collision/facets.h): a vertex or a particle against a
    // triangle or the environment, by the same law at the touching point; the
    // faceted side does not turn (its lattice rotates with its particles).
    w.faceted = !Lean && w.c->involvesFacets();
    w.rimmed = !Lean && w.c->rim >= 0;  // (Lean: neither facets nor rims)
    w.squeezeRate = 0.0;
    w.armLengthA = -1.0;
    w.armLengthB = -1.0;
    w.facetStiffness = 0.0;
  }

  // The touching point's kinematics, by the contact's geometry: the narrow
  // phase's dispatch over its sides' kinds.
  void sideGeometry() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    if (w.faceted) {
      facetSide();
    } else if (w.other >= 0) {
      pairSide();
    } else if (w.rimmed) {
      rimSide();
    } else {
      FrictionTrial& t = *w.t;
      t.relative = p_[w.a];
      w.relativeVelocity = v_[w.a];
      t.armA = w.c->normal * -model_.radius[w.a];  // the point on a's own surface
      t.armB = Vec3{};
      ++chunk_.stats.environmentContacts;
    }
  }

  // A vertex or a particle on a triangle, or a vertex on the environment.
  void facetSide() {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    Contact& c = *w.c;
    facetKinematics(model_, tables_, p_, v_, w.before, c, facet_);
    if (w.before != nullptr) w.before = &facet_.previous;
    t.relative = facet_.relative;
    w.relativeVelocity = facet_.relativeVelocity;
    w.inverseMass = 1.0 / facet_.reducedMass;
    w.smallerRadius = facet_.radius;
    t.armA = c.vertex >= 0 ? Vec3{} : c.normal * -(model_.radius[w.a] + c.depth);
    t.armB = Vec3{};
    w.facetStiffness = facetExtraStiffness(model_, w.k->stiffness, c);
    ++chunk_.stats.facetContacts;
  }

  // Two particles: worked out with its batch (nextBatch), or now (a pair the
  // trees found).
  void pairSide() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    Contact& c = *w.c;
    const std::int32_t b = w.other;
    if (w.seed->full != -1) pairGeometry(model_, p_, w.a, b, treePair_);
    const PairGeometry& g = w.seed->full == -1 ? batch_[w.index - batchBegin_] : treePair_;
    t.relative = g.relative;
    c.normal = g.normal;
    c.depth = g.depth;
    pairArms(g.normal, g.depth, model_.radius[w.a], model_.radius[b], t.armA, t.armB);
    w.armLengthA = g.armLengthA;
    w.armLengthB = g.armLengthB;
    w.smallerRadius = std::min(w.smallerRadius, model_.radius[b]);
    w.relativeVelocity = v_[w.a] - v_[b];
    w.inverseMass += tables_.contactInverseMass[b];
    ++chunk_.stats.particleContacts;
  }

  // A round rim or ball (rigid about its centre): the contact point on the
  // surface is c.arm from the body's centre.
  void rimSide() {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    const Contact& c = *w.c;
    const RimRing& round = model_.rims[static_cast<std::size_t>(c.rim)];
    t.ring = static_cast<std::int32_t>(chunk_.rings.size());
    chunk_.rings.push_back(ringMotion(model_, p_, v_, round));
    ring_ = chunk_.rings.back();
    t.relative = ring_.center;
    w.relativeVelocity = ring_.velocity;
    w.inverseMass = 1.0 / ring_.mass;
    t.armA = c.arm;
    t.armB = Vec3{};
    // A ring: d = n·(c + R u) - h - r changes with its turning and size too.
    // A ball: d = n·c - h - R with R fixed, and its turning moves no depth.
    if (round.isSphere()) {
      w.smallerRadius = round.sphereRadius;
    } else {
      w.squeezeRate = (dot(c.normal, c.arm) + model_.radius[w.a]) / ring_.radius;
    }
    ++chunk_.stats.environmentContacts;
  }

  // MODEL §3.1: F = (-κ_c d - μ_c ḋ) k̂ for d < 0, clamped at >= 0; its
  // spring's energy, the power of its non-elastic part, the deepest contact.
  void applyNormalLaw() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    Contact& c = *w.c;
    const PairParameters& k = *w.k;
    const Vec3 n = c.normal;  // (a copy: read back from c, it stalls on its own stores)
    const double d = c.depth;
    const double dDot = w.rimmed ? dot(w.relativeVelocity + cross(ring_.omega, w.t->armA), n) +
                                       w.squeezeRate * ring_.radiusRate
                                 : dot(w.relativeVelocity, n);
    const law::NormalLoad load = law::normalLaw(k.stiffness, k.damping, d, dDot);
    const double normalForce = load.force;
    c.normalForce = normalForce;
    w.normalForce = normalForce;
    tally_.potential += load.potential;
    tally_.dissipativePower += load.dissipation;
    w.normal = n * normalForce;
    ContactStats& stats = chunk_.stats;
    stats.maxPenetration = std::max(stats.maxPenetration, -c.depth);
    // -d / r, a division, only where it may be the deepest so far: the test
    // lets through every quotient above the maximum (its rounding is far below
    // the 1e-9 margin).
    if (-c.depth > stats.maxPenetrationFraction * w.smallerRadius * (1.0 - 1e-9)) {
      stats.maxPenetrationFraction =
          std::max(stats.maxPenetrationFraction, -c.depth / w.smallerRadius);
    }
    FrictionTrial& t = *w.t;
    t.group = -1;
    takeFrictionParameters(t, k);
    w.rollMoment = Vec3{};
  }

  // The contact points' velocities: the rotation of each body adds ω × arm;
  // the rolling resistance's moment.
  void turnSides() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    Contact& c = *w.c;
    w.ta = Turning{};
    w.tb = Turning{};
    if (w.rimmed) {  // the ring turns as a whole (kind 3)
      w.ta.kind = 3;
      w.ta.omega = ring_.omega;
      w.ta.armInverseInertia = squaredNorm(t.armA) * ring_.largestInverse;
    } else if (Lean || c.vertex < 0) {
      w.ta = turningOf(model_, tables_, cache_, p_, v_, in_.spin, w.a,
                       w.armLengthA >= 0.0 ? w.armLengthA : norm(t.armA), t.inverseA);
    }
    if (w.other >= 0 && (Lean || c.facet < 0)) {
      w.tb = turningOf(model_, tables_, cache_, p_, v_, in_.spin, w.other,
                       w.armLengthB >= 0.0 ? w.armLengthB : norm(t.armB), t.inverseB);
    }
    t.turnA = w.ta.kind;
    t.turnB = w.tb.kind;
    w.rollVelocity = cross(w.ta.omega, t.armA) - cross(w.tb.omega, t.armB);
    c.rollVelocity = w.rollVelocity;
    if (w.k->rollingResistance > 0.0) {
      w.rollMoment = rollingResistanceMoment(*w.k, c, w.ta.omega, w.tb.omega,
                                             surfaceRadius(model_, c), tally_);
    }
  }

  // MODEL §3.3 with an anchor: δ_t is the tangential part of the displacement
  // from where the contact stuck; the slip, the spring's and damper's loads.
  // (Its new anchor is set when its group has decided: frictionForce.)
  void frictionTrial() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    Contact& c = *w.c;
    const PairParameters& k = *w.k;
    const Vec3 pointVelocity = w.relativeVelocity + w.rollVelocity;
    // m_eff at the contact point: 1/m_a + 1/m_b plus the rotations' share.
    const double tangentialInverse =
        w.inverseMass + w.ta.armInverseInertia + (w.other >= 0 ? w.tb.armInverseInertia : 0.0);
    t.tangentialDamping =
        law::tangentialDamping(k.tangentialDampingRatio, k.tangentialStiffness, tangentialInverse);
    settle(w.inverseMass > 0.0 ? tangentialInverse / w.inverseMass : 1.0, t.tangentialDamping);
    anchorOffset();
    const Vec3 n = c.normal;
    c.slip = tangentialPart(pointVelocity, n);
    t.slipSpeed = norm(c.slip);
    const auto loads =
        law::anchorLoads(t.delta, c.slip, k.tangentialStiffness, t.tangentialDamping);
    t.elastic = loads.elastic;
    t.damper = loads.damper;
    // A sliding contact may stick again when its slip has fallen below the stick
    // velocity, or has reversed since the last evaluation: kinetic friction would
    // have stopped it within the step (without this, μ_k F_n flips the slip back
    // and forth every step, a chatter that never comes to rest).
    const Contact* before = w.before;
    const bool reversed = before != nullptr && dot(c.slip, before->slip) < 0.0;
    t.slow = t.slipSpeed <= stickVelocity_ || reversed;
    t.frictionLoad = k.staticFriction * w.normalForce;
    t.tangentialInverse = tangentialInverse;
    t.hadBefore = before != nullptr;
    if (t.hadBefore) t.slipBefore = before->slip;
  }

  // δ_t from the anchor of the last evaluation (the contact's own point for a
  // new one), as the history left it.
  void anchorOffset() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    const Contact& c = *w.c;
    const Contact* before = w.before;
    const double kt = w.k->tangentialStiffness;
    t.previousEnergy = 0.0;
    t.regimeBefore = kSticking;
    t.giveWayBefore = 0.0;
    Vec3 anchor = t.relative;
    if (before != nullptr) {
      anchor = before->anchor;
      t.regimeBefore = before->sliding;
      t.giveWayBefore = before->giveWay;
      t.previousEnergy = before->anchorEnergy;
    }
    const Vec3 n = c.normal;
    t.delta = tangentialPart(t.relative - anchor, n);
    if (before != nullptr && t.regimeBefore != kSliding &&
        ((w.faceted && before->facet != c.facet) || dot(before->normal, n) < kNormalTurn)) {
      // A vertex's contact moved to another triangle, or a contact's normal
      // turned at once (inside a box past the middle of its faces, a
      // heightfield's top to its side): near an edge the normal jumps (to the
      // other face's). The anchor's offset projected on the new plane is not
      // the one it held: keep no more than it held, and release what the new
      // plane takes off (else the spring's energy jumps at no motion and the
      // adaptive step stalls on it).
      const double held = squaredNorm(tangentialPart(t.relative - anchor, before->normal));
      const double now = squaredNorm(t.delta);
      if (now > held) t.delta = t.delta * std::sqrt(held / now);
      tally_.releasedEnergy += 0.5 * kt * held - 0.5 * kt * squaredNorm(t.delta);
    }
    if (t.regimeBefore == kSliding) {
      // A sliding anchor follows the slip: over the last step the contact was
      // loaded by kinetic friction (its work booked as dissipation), not by its
      // spring, so the spring holds the offset it had, F_t = -k_t δ_t (MODEL §3.3);
      // what the new normal's projection takes off is released.
      t.delta = tangentialPart(before->frictionForce * (-1.0 / kt), n);
      tally_.releasedEnergy += t.previousEnergy - 0.5 * kt * squaredNorm(t.delta);
    }
  }

  // Lean: the group (the contact alone) decides, its friction and loads follow.
  // Else the contact joins its group of the run (a's object with the other's
  // object or the environment item).
  void joinOrDecide() ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTrial& t = *w.t;
    if constexpr (Lean) {
      FrictionGroup group;
      t.group = 0;
      joinGroup(group, t);
      decideGroup(group, &t, 1, 0);
      finishAlone(&group);
    } else {
      const std::int64_t otherBody = w.other >= 0 ? groupKey(tables_, w.other) : w.other;
      std::size_t g = 0;
      while (g < chunk_.groups.size() && chunk_.groups[g].other != otherBody) ++g;
      if (g == chunk_.groups.size()) chunk_.groups.emplace_back().other = otherBody;
      t.group = static_cast<std::int32_t>(g);
      joinGroup(chunk_.groups[g], t);
    }
  }

  // The contact's loads once its sides' turning is known: left for the gather
  // by particle, or deferred (with what the serial pass needs: deferLoad).
  void settle(double rotationFactor, double tangentialDamping) ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    const FrictionTrial& t = *w.t;
    const law::Rates rates =
        contactRates(tables_, *w.k, w.a, w.other, rotationFactor, tangentialDamping);
    ContactLoad& load = Lean      ? leanLoad_
                        : direct_ ? chunk_.runLoads[w.index - runFirst_]
                                  : cache_.loads[w.index];
    load.a = w.a;
    load.other = w.other;
    load.deferred = !Lean && (w.faceted || w.rimmed || t.turnA == 2 || t.turnB == 2);
    if (load.deferred) {
      deferLoad(rates);
      return;
    }
    load.force = w.normal;
    load.torqueA = t.turnA == 1 ? w.rollMoment : Vec3{};
    load.torqueB = t.turnB == 1 ? w.rollMoment * -1.0 : Vec3{};
    load.rates = rates;
  }

  // A deferred contact: what the serial pass (applyDeferred) needs of it.
  void deferLoad(const law::Rates& rates) {
    Current& w = w_;
    const FrictionTrial& t = *w.t;
    FrictionApplication& application = cache_.applications[w.index];
    application.kind = FrictionApplication::kNone;
    application.force = Vec3{};
    application.normal = w.normal;
    application.rollMoment = w.rollMoment;
    application.rolling = w.k->rollingResistance > 0.0;
    application.armA = t.armA;
    application.armB = t.armB;
    application.squeeze = w.normalForce * w.squeezeRate;
    application.rates = rates;
    application.facetStiffness = w.facetStiffness;
    application.ring = t.ring;
    application.turnA = static_cast<std::int8_t>(t.turnA);
    application.turnB = static_cast<std::int8_t>(t.turnB);
    application.inverse = -1;
    if (t.turnA == 2 || t.turnB == 2) {
      application.inverse = static_cast<std::int32_t>(chunk_.inverses.size() / 12);
      chunk_.inverses.insert(chunk_.inverses.end(), t.inverseA, t.inverseA + 6);
      chunk_.inverses.insert(chunk_.inverses.end(), t.inverseB, t.inverseB + 6);
    }
    chunk_.deferred.push_back(static_cast<std::int32_t>(w.index));
  }

  // Lean: the contact's friction (its group, itself, has decided: `group`;
  // null without friction) and its loads, now.
  void finishAlone(const FrictionGroup* group) ROBOPHI_ALWAYS_INLINE {
    Current& w = w_;
    FrictionTerms terms;
    contactFriction(*w.t, group, *w.c, leanLoad_, terms);
    deliverLoad(leanLoad_, direct_ ? nullptr : &cache_.loads[w.index], in_.force, in_.torque,
                cache_);
    chunk_.runTerms[w.index - runFirst_] = {terms.released, terms.dissipated, w.c->anchorEnergy};
  }

  // A contact without friction holds no anchor (its old one's energy is released).
  void withoutAnchor() {
    Current& w = w_;
    Contact& c = *w.c;
    c.anchor = w.t->relative;
    c.anchorEnergy = 0.0;
    c.slip = Vec3{};
    c.giveWay = 0.0;
    if (w.before != nullptr) tally_.releasedEnergy += w.before->anchorEnergy;
    settle(1.0, 0.0);
    if constexpr (Lean) finishAlone(nullptr);
  }

  // A run: the contacts from the first of a's object (the first with friction)
  // to the next object's. Its groups decide, and its contacts' friction is
  // worked out, when it ends (its trials are still in the chunk).
  void finishRun(std::size_t end) {
    if constexpr (Lean) {  // (its contacts have decided and added their loads)
      for (std::size_t k = 0; k < end - runFirst_; ++k) {
        const ContactChunk::RunTerms& terms = chunk_.runTerms[k];
        tally_.releasedEnergy += terms.released;
        tally_.dissipativePower -= terms.dissipated;
        tally_.potential += terms.anchorEnergy;
      }
      runFirst_ = end;
      return;
    }
    decideGroups(chunk_.groups, chunk_.trials.data(), end - runFirst_);
    for (std::size_t index = runFirst_; index < end; ++index) runContactFriction(index);
    chunk_.groups.clear();
    runFirst_ = end;
  }

  // A contact of the run that ended: its friction once its group decided, onto
  // its loads (added now when direct) or its deferred application.
  void runContactFriction(std::size_t index) {
    Contact& c = contacts_[index];
    const FrictionTrial& t = chunk_.trials[index - runFirst_];
    FrictionTerms terms;
    ContactLoad& load = direct_ ? chunk_.runLoads[index - runFirst_] : cache_.loads[index];
    const Vec3 friction = contactFriction(
        t, t.group >= 0 ? &chunk_.groups[static_cast<std::size_t>(t.group)] : nullptr, c, load,
        terms);
    if (!load.deferred) {
      // As the scatter in accumulateContacts, contact by contact.
      if (direct_) scatterLoad(load, *in_.force, *in_.torque, cache_);
    } else if (t.group >= 0) {
      FrictionApplication& application = cache_.applications[index];
      application.force = friction;
      application.kind = c.involvesFacets() ? FrictionApplication::kFacet
                         : c.rim >= 0       ? FrictionApplication::kRing
                                            : FrictionApplication::kParticles;
    }
    tally_.releasedEnergy += terms.released;
    tally_.dissipativePower -= terms.dissipated;
    tally_.potential += c.anchorEnergy;  // ½ k_t |δ_t|² of the friction anchor
  }

  static constexpr std::size_t kBatch = detail::PairLaneBatch::kSize;

  const StageInput& in_;
  const Model& model_;
  const ContactTables& tables_;
  const std::vector<Vec3>& p_;
  const std::vector<Vec3>& v_;
  const std::vector<Contact>& previous_;
  ContactScratch& cache_;
  std::vector<Contact>& contacts_;
  ContactChunk& chunk_;
  const double stickVelocity_;
  const bool direct_;
  StageTally tally_;
  std::size_t runFirst_;
  std::size_t old_;
  const std::size_t oldEnd_;
  std::int64_t runObject_ = -1;
  PairParameters overrideParameters_;
  // Lean: the current contact's trial and loads.
  FrictionTrial leanTrial_;
  ContactLoad leanLoad_;
  // Per contact, filled only for facet and rim contacts (kept out of Current:
  // they are large, and most contacts need neither).
  FacetKinematics facet_;
  RingMotion ring_;  // the current rim contact's (a copy of chunk.rings.back())
  PairGeometry batch_[kBatch];
  PairGeometry treePair_;  // (a pair the trees found: not in the batch)
  std::size_t batchBegin_, batchEnd_;
  const bool lanes_;
  detail::PairLaneBatch laneBatch_;  // (its lanes are written before they are read)
  bool useLanes_[kBatch];
  Current w_;
};

// The serial pass: a deferred contact's loads, in contact order (they reach
// particles other than its two: a facet's, a ring's, an LS neighbourhood).
void applyDeferred(const StageInput& in, const ContactChunk& chunk, std::vector<Vec3>& f,
                   std::vector<Vec3>& torque) {
  const Model& model = in.model;
  const std::vector<Vec3>& p = in.p;
  for (const std::int32_t index : chunk.deferred) {
    const Contact& c = in.cache.freshContacts[static_cast<std::size_t>(index)];
    const FrictionApplication& application = in.cache.applications[static_cast<std::size_t>(index)];
    const std::int32_t a = c.a, other = c.other;
    const RimRing* rim = c.rim >= 0 ? &model.rims[static_cast<std::size_t>(c.rim)] : nullptr;
    const RingMotion* ring =
        application.ring >= 0 ? &chunk.rings[static_cast<std::size_t>(application.ring)] : nullptr;
    const double* inverseA =
        application.inverse >= 0
            ? chunk.inverses.data() + 12 * static_cast<std::size_t>(application.inverse)
            : nullptr;
    const double* inverseB = inverseA != nullptr ? inverseA + 6 : nullptr;
    // The normal force.
    const Vec3& normal = application.normal;
    if (c.involvesFacets()) {
      distributeFacetForce(model, c, normal, f);
    } else if (rim != nullptr) {
      applyRingLoad(model, in.tables, p, *rim, *ring, normal, cross(application.armA, normal),
                    application.squeeze, f, torque);
    } else {
      f[a] += normal;
      if (other >= 0) f[other] -= normal;
    }
    addDeferredRates(model, c, application, in.cache);
    // Rolling resistance.
    if (application.rolling) {
      const Vec3& moment = application.rollMoment;
      if (rim != nullptr)
        applyRingLoad(model, in.tables, p, *rim, *ring, Vec3{}, moment, 0.0, f, torque);
      applyMoment(model, in.tables, p, application.turnA, inverseA, a, moment, f, torque);
      if (other >= 0)
        applyMoment(model, in.tables, p, application.turnB, inverseB, other, moment * -1.0, f,
                    torque);
    }
    // Friction at the contact point.
    if (application.kind == FrictionApplication::kNone) continue;
    const Vec3& tangential = application.force;
    if (application.kind == FrictionApplication::kFacet) {
      distributeFacetForce(model, c, tangential, f);
    } else if (application.kind == FrictionApplication::kRing) {
      applyRingLoad(model, in.tables, p, *rim, *ring, tangential,
                    cross(application.armA, tangential), 0.0, f, torque);
    } else {
      f[a] += tangential;
      if (other >= 0) f[other] -= tangential;
    }
    applyMoment(model, in.tables, p, application.turnA, inverseA, a,
                cross(application.armA, tangential), f, torque);
    if (other >= 0) {
      applyMoment(model, in.tables, p, application.turnB, inverseB, other,
                  cross(application.armB, tangential * -1.0), f, torque);
    }
  }
}

// Where each particle's loads are: contacts are sorted by a, so a's are a range
// (aStart); the other side's simple ones are listed by particle (otherStart,
// otherContact), in contact order.
void indexLoads(std::size_t particles, ContactScratch& cache) {
  const std::vector<ContactLoad>& loads = cache.loads;
  cache.aStart.assign(particles + 1, 0);
  cache.otherStart.assign(particles + 1, 0);
  for (const ContactLoad& load : loads) {
    ++cache.aStart[static_cast<std::size_t>(load.a) + 1];
    if (!load.deferred && load.other >= 0)
      ++cache.otherStart[static_cast<std::size_t>(load.other) + 1];
  }
  for (std::size_t i = 0; i < particles; ++i) {
    cache.aStart[i + 1] += cache.aStart[i];
    cache.otherStart[i + 1] += cache.otherStart[i];
  }
  cache.otherContact.resize(static_cast<std::size_t>(cache.otherStart[particles]));
  cache.otherFill.assign(cache.otherStart.begin(), cache.otherStart.end() - 1);
  for (std::size_t index = 0; index < loads.size(); ++index) {
    const ContactLoad& load = loads[index];
    if (load.deferred || load.other < 0) continue;
    cache.otherContact[static_cast<std::size_t>(
        cache.otherFill[static_cast<std::size_t>(load.other)]++)] =
        static_cast<std::int32_t>(index);
  }
}

// The chunks of the contact list: about kContactChunk contacts each, cut only
// where a's object changes (a run, and so a group's decision, stays in one
// chunk), each with the history contacts from its first key on. Returns their count.
std::size_t cutChunks(const ContactTables& tables, const std::vector<Contact>& previous,
                      ContactScratch& cache) {
  const std::size_t count = cache.seeds.size();
  constexpr std::size_t kContactChunk = 512;
  std::size_t chunkCount = 0;
  for (std::size_t begin = 0; begin < count;) {
    std::size_t end = std::min(count, begin + kContactChunk);
    if (end < count) {
      const std::int64_t object = groupKey(tables, cache.seeds[end - 1].a());
      while (end < count && groupKey(tables, cache.seeds[end].a()) == object) ++end;
    }
    if (cache.chunks.size() <= chunkCount) cache.chunks.emplace_back();
    ContactChunk& chunk = cache.chunks[chunkCount++];
    chunk.begin = begin;
    chunk.end = end;
    const Contact::Key first = cache.seeds[begin].key;
    chunk.historyBegin = begin == 0
                             ? 0
                             : static_cast<std::size_t>(
                                   std::lower_bound(previous.begin(), previous.end(), first,
                                                    [](const Contact& c, const Contact::Key& key) {
                                                      return c.key() < key;
                                                    }) -
                                   previous.begin());
    if (chunkCount > 1) cache.chunks[chunkCount - 2].historyEnd = chunk.historyBegin;
    begin = end;
  }
  if (chunkCount > 0) cache.chunks[chunkCount - 1].historyEnd = previous.size();
  return chunkCount;
}

// The neighbourhood rotations of the particles in contact that turn with
// theirs (MODEL §3.3), once each, into cache.turning.
void prepareTurning(const Model& model, const ContactTables& tables, const std::vector<Vec3>& p,
                    const std::vector<Vec3>& v, int threads, ContactScratch& cache) {
  const auto particles = static_cast<std::size_t>(model.particleCount());
  TurningCache& turning = cache.turning;
  if (turning.slot.size() != particles) turning.slot.assign(particles, -1);
  turning.particles.clear();
  if (!model.contact.rolling || tables.rollNeighbour.empty()) return;
  const auto mark = [&](std::int32_t i) {
    if (i < 0 || turning.slot[static_cast<std::size_t>(i)] >= 0 ||
        turningKind(model, tables, i) != 2)
      return;
    turning.slot[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(turning.particles.size());
    turning.particles.push_back(i);
  };
  for (const ContactSeed& seed : cache.seeds) {
    mark(seed.a());
    mark(seed.other());
  }
  const std::size_t turners = turning.particles.size();
  turning.omega.resize(turners);
  turning.inverse.resize(6 * turners);
  turning.largest.resize(turners);
  detail::parallelFor(
      threads, static_cast<std::int64_t>(turners), [&](std::int64_t begin, std::int64_t end) {
        for (auto k = static_cast<std::size_t>(begin); k < static_cast<std::size_t>(end); ++k) {
          turning.largest[k] =
              neighbourhoodRotation(model, tables, p, v, turning.particles[k], turning.omega[k],
                                    turning.inverse.data() + 6 * k);
        }
      });
}

}  // namespace

void findContactLoads(const Model& model, const ContactTables& tables, std::int64_t revision,
                      int threads, const std::vector<Vec3>& p, const std::vector<Vec3>& v,
                      const std::vector<Vec3>& spin, const std::vector<Contact>& previous,
                      ContactScratch& scratch, std::vector<Vec3>* force,
                      std::vector<Vec3>* torque) {
  scratch.chunkCount = 0;
  scratch.direct = false;
  if (!model.contact.enabled || model.particleCount() == 0) return;
  ContactScratch& cache = prepareContactScratch(model, tables, revision, p, scratch);
  detectContacts(model, p, v, threads, previous, cache);

  const auto particles = static_cast<std::size_t>(model.particleCount());
  if (cache.contactRateSum.size() != particles) cache.contactRateSum.assign(particles, {});
  const std::size_t count = cache.seeds.size();
  // (Resized, not cleared: the buffer swapped back holds the list of two
  // evaluations ago, so only the difference is constructed.)
  cache.freshContacts.resize(count);
  cache.applications.resize(count);

  const std::size_t chunkCount = cutChunks(tables, previous, cache);
  prepareTurning(model, tables, p, v, threads, cache);

  // Fewer contacts than a parallel loop's minimum: this thread alone.
  const int stageThreads =
      count >= static_cast<std::size_t>(detail::kParallelMinimum) ? threads : 1;
  // Whether a contact may be deferred (a facet's, a rim's, an LS-turning
  // particle's). One thread, and none can: the chunks add the loads as they go
  // (StageInput::force), when the caller allows it.
  const bool deferrable = !model.surfaceVertices.empty() || !model.surfaceTriangles.empty() ||
                          !model.rims.empty() ||
                          (model.contact.rolling && !tables.rollNeighbour.empty());
  const bool direct = force != nullptr && stageThreads <= 1 && !deferrable;
  if (!direct) cache.loads.resize(count);
  cache.chunkCount = chunkCount;
  cache.stageThreads = stageThreads;
  cache.direct = direct;
  const StageInput input{model,
                         tables,
                         p,
                         v,
                         spin,
                         previous,
                         cache,
                         direct ? force : nullptr,
                         direct ? torque : nullptr};
  struct Context {
    const StageInput* input;
    ContactChunk* chunks;
    bool lean;
  } context{&input, cache.chunks.data(), tables.singleParticleBodies && !deferrable};
  detail::runChunks(
      stageThreads, static_cast<std::int64_t>(chunkCount),
      [](void* raw, std::int64_t c) {
        const Context& x = *static_cast<const Context*>(raw);
        if (x.lean) {
          ChunkWalk<true>(*x.input, x.chunks[c]).run();
        } else {
          ChunkWalk<false>(*x.input, x.chunks[c]).run();
        }
      },
      &context);
}

namespace {

// The chunks' sums and statistics, in chunk order, into the stage's; the
// deferred loads, in contact order (applyDeferred).
StageTally sumChunks(const StageInput& input, std::vector<Vec3>& f, std::vector<Vec3>& torque) {
  ContactScratch& cache = input.cache;
  StageTally tally;
  ContactStats& stats = cache.stats;
  for (std::size_t c = 0; c < cache.chunkCount; ++c) {
    const ContactChunk& chunk = cache.chunks[c];
    tally.potential += chunk.potential;
    tally.dissipativePower += chunk.dissipativePower;
    tally.releasedEnergy += chunk.releasedEnergy;
    stats.particleContacts += chunk.stats.particleContacts;
    stats.environmentContacts += chunk.stats.environmentContacts;
    stats.facetContacts += chunk.stats.facetContacts;
    stats.maxPenetration = std::max(stats.maxPenetration, chunk.stats.maxPenetration);
    stats.maxPenetrationFraction =
        std::max(stats.maxPenetrationFraction, chunk.stats.maxPenetrationFraction);
    applyDeferred(input, chunk, f, torque);
  }
  return tally;
}

// MODEL §3.7, the contacts' stability limit of particle i from the sums of its
// contacts' stiffness and damping, by Gershgorin as for the connectors
// (estimateStability): ω² <= 2 Σk / m, 2ζω <= 2 Σc / m, δ < 2/ω (√(1+ζ²) - ζ).
inline double contactStabilityStep(const ContactTables& tables, std::size_t i,
                                   const law::Rates& sum) {
  const double omega = std::sqrt(2.0 * sum.stiffness * tables.contactInverseMass[i]);
  const double dampingRate = 2.0 * sum.damping * tables.contactInverseMass[i];
  return dampedCriticalStep(omega, dampingRate);
}

// Particle i's stability sums, once its loads are in: zeroed again; its limit
// (a rigid tree's particle: its body's, addRigidTreeTerms) into `step`.
// (`sum` by value: it may be the particle's own entry, zeroed here.)
inline void takeStabilitySums(const ContactTables& tables, ContactScratch& cache, std::size_t i,
                              law::Rates sum, double& step) {
  if (sum.stiffness == 0.0 && sum.damping == 0.0) return;
  cache.contactRateSum[i] = {};
  if (sum.stiffness != 0.0 && tables.treeOf[i] < 0)
    step = std::min(step, contactStabilityStep(tables, i, sum));
}

// One thread: the pair contacts' loads scattered in contact order (unless the
// chunks added them as they went), then each particle's stability sums.
double gatherSerial(const ContactTables& tables, ContactScratch& cache, std::size_t particles,
                    std::vector<Vec3>& f, std::vector<Vec3>& torque) {
  double criticalStep = std::numeric_limits<double>::infinity();
  const std::size_t count = cache.direct ? 0 : cache.seeds.size();
  for (std::size_t index = 0; index < count; ++index) {
    const ContactLoad& load = cache.loads[index];
    if (!load.deferred) scatterLoad(load, f, torque, cache);
  }
  for (std::size_t i = 0; i < particles; ++i)
    takeStabilitySums(tables, cache, i, cache.contactRateSum[i], criticalStep);
  return criticalStep;
}

// Particle i's pair-contact loads, gathered: the contacts where it is the other
// side, then those where it is a, in contact order (the scatter's terms in its
// order: a pair contact has a < other). Returns its limit into `step`.
inline void gatherParticle(const ContactTables& tables, ContactScratch& cache, std::size_t i,
                           std::vector<Vec3>& f, std::vector<Vec3>& torque, double& step) {
  const ContactLoad* loads = cache.loads.data();
  Vec3 force = f[i], moment = torque[i];
  law::Rates sum = cache.contactRateSum[i];
  for (std::int32_t k = cache.otherStart[i]; k < cache.otherStart[i + 1]; ++k) {
    const ContactLoad& load = loads[cache.otherContact[static_cast<std::size_t>(k)]];
    force -= load.force;
    moment += load.torqueB;
    sum.add(load.rates);
  }
  for (std::int32_t index = cache.aStart[i]; index < cache.aStart[i + 1]; ++index) {
    const ContactLoad& load = loads[index];
    if (load.deferred) continue;
    force += load.force;
    moment += load.torqueA;
    sum.add(load.rates);
  }
  f[i] = force;
  torque[i] = moment;
  takeStabilitySums(tables, cache, i, sum, step);
}

// On threads: a gather by particle (gatherParticle), the smallest limit of each
// chunk of particles, then of all.
double gatherThreads(const ContactTables& tables, ContactScratch& cache, std::size_t particles,
                     std::vector<Vec3>& f, std::vector<Vec3>& torque) {
  indexLoads(particles, cache);
  const std::int64_t gatherChunks =
      (static_cast<std::int64_t>(particles) + detail::kParallelChunk - 1) / detail::kParallelChunk;
  cache.chunkSteps.assign(static_cast<std::size_t>(gatherChunks),
                          std::numeric_limits<double>::infinity());
  detail::parallelFor(
      cache.stageThreads, static_cast<std::int64_t>(particles),
      [&](std::int64_t begin, std::int64_t end) {
        double step = std::numeric_limits<double>::infinity();
        for (auto i = static_cast<std::size_t>(begin); i < static_cast<std::size_t>(end); ++i)
          gatherParticle(tables, cache, i, f, torque, step);
        cache.chunkSteps[static_cast<std::size_t>(begin / detail::kParallelChunk)] = step;
      });
  double criticalStep = std::numeric_limits<double>::infinity();
  for (const double step : cache.chunkSteps) criticalStep = std::min(criticalStep, step);
  return criticalStep;
}

}  // namespace

void applyContactLoads(const Model& model, const ContactTables& tables, const std::vector<Vec3>& p,
                       const std::vector<Vec3>& v, const std::vector<Vec3>& spin,
                       const std::vector<Contact>& previous, ContactScratch& cache,
                       Evaluation& out) {
  if (!model.contact.enabled || model.particleCount() == 0) {
    out.contactCriticalStep = std::numeric_limits<double>::infinity();
    out.contacts.clear();
    out.energy.contact = 0.0;
    out.releasedAnchorEnergy = 0.0;
    out.contactStats = ContactStats{};
    return;
  }
  const auto particles = static_cast<std::size_t>(model.particleCount());
  std::vector<Vec3>& f = out.force;
  std::vector<Vec3>& torque = out.torque;
  // (The serial pass of deferred loads reads the stage's input, not its `force`.)
  const StageInput input{model, tables, p, v, spin, previous, cache};
  StageTally tally = sumChunks(input, f, torque);
  if (cache.seeds.empty()) {  // every contact of the history opened
    for (const Contact& c : previous) tally.releasedEnergy += c.anchorEnergy;
  }
  // The loads of the pair contacts and each particle's stability limit: on
  // threads, a gather by particle; on one, the scatter in contact order, which
  // adds the same terms in the same order.
  const double criticalStep = cache.stageThreads <= 1
                                  ? gatherSerial(tables, cache, particles, f, torque)
                                  : gatherThreads(tables, cache, particles, f, torque);
  for (const std::int32_t i : cache.turning.particles)
    cache.turning.slot[static_cast<std::size_t>(i)] = -1;
  std::swap(out.contacts, cache.freshContacts);

  const double viscousPower = accumulateViscosity(model, p, v, f, cache);
  out.energy.contact = tally.potential;
  // (With the ridges' approach: an edge contact starts at the surface, edges.h.)
  out.contactCriticalStep = std::min(criticalStep, cache.edgeApproachStep);
  out.dissipativePower += tally.dissipativePower + viscousPower;
  out.releasedAnchorEnergy = tally.releasedEnergy;
  out.contactStats = cache.stats;
}

double deepestPenetrationFraction(const Model& model, const std::vector<Contact>& contacts) {
  double deepest = 0.0;
  for (const Contact& c : contacts) {
    double r = surfaceRadius(model, c);
    if (c.other >= 0) r = std::min(r, model.radius[c.other]);
    deepest = std::max(deepest, -c.depth / r);
  }
  return deepest;
}

}  // namespace robophi
