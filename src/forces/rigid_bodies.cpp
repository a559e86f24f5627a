// Rigid bodies of particles and the links between them (MODEL §1.7): each body's
// best-fit rigid motion, shape matching towards it, and the body links' penalty
// wrenches, spread over the bodies' particles as the rigid motion they cause.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "forces/forces.h"

namespace robophi {

namespace {

using Matrix33 = std::array<std::array<double, 3>, 3>;

Vec3 times(const Matrix33& m, const Vec3& v) {
  return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
          m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
          m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

Vec3 column(const Matrix33& m, int c) { return {m[0][c], m[1][c], m[2][c]}; }

struct UnitQuaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

UnitQuaternion multiply(const UnitQuaternion& a, const UnitQuaternion& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Matrix33 matrixOf(const UnitQuaternion& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

// The rotation R that maximises trace(Rᵀ A) (A = Σ m_i p_i r_iᵀ): the rotational part
// of A, by the iteration of Müller et al. (2016), started from the best of the
// identity and the three half turns (so that no start sits on the iteration's
// unstable half-turn equilibrium). Works for flat bodies (A of rank 2).
Matrix33 rotationOf(const Matrix33& a) {
  const std::array<UnitQuaternion, 4> starts = {UnitQuaternion{1, 0, 0, 0}, UnitQuaternion{0, 1, 0, 0},
                                            UnitQuaternion{0, 0, 1, 0}, UnitQuaternion{0, 0, 0, 1}};
  UnitQuaternion q = starts[0];
  double best = -1e300;
  for (const UnitQuaternion& s : starts) {
    const Matrix33 r = matrixOf(s);
    double trace = 0.0;
    for (int c = 0; c < 3; ++c) trace += dot(column(r, c), column(a, c));
    if (trace > best) {
      best = trace;
      q = s;
    }
  }
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Matrix33 r = matrixOf(q);
    Vec3 torque{};
    double alignment = 0.0;
    for (int c = 0; c < 3; ++c) {
      torque += cross(column(r, c), column(a, c));
      alignment += dot(column(r, c), column(a, c));
    }
    const Vec3 omega = torque / (std::abs(alignment) + 1e-300);
    const double angle = norm(omega);
    if (!(angle > 1e-13)) break;
    const Vec3 axis = omega / angle;
    const double s = std::sin(0.5 * angle);
    q = multiply({std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s}, q);
    const double length = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / length, q.x / length, q.y / length, q.z / length};
  }
  return matrixOf(q);
}

}  // namespace

Vec3 RigidMotion::solve(const Vec3& t) const { return times(inverseInertia, t); }

Vec3 RigidMotion::rotate(const Vec3& r) const { return times(rotation, r); }

Vec3 RigidMotion::velocityAt(const Vec3& point) const {
  return velocity + cross(spin, point - center);
}

namespace {

// The centre's velocity v̄ = Σ m_i v_i / M and the spin ω = I⁻¹ Σ m_i (p_i − p̄) × (v_i − v̄)
// of a motion whose mass, centre and inverse inertia are set.
void measureVelocity(const Model& model, const std::vector<ParticleIndex>& particles,
                     const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                     RigidMotion& m) {
  Vec3 momentum{}, angular{};
  for (ParticleIndex i : particles) momentum += velocity[i] * model.mass[i];
  m.velocity = momentum / m.mass;
  for (ParticleIndex i : particles)
    angular += cross(position[i] - m.center, velocity[i] - m.velocity) * model.mass[i];
  m.spin = m.solve(angular);
}

}  // namespace

RigidMotion rigidMotion(const Model& model, const std::vector<ParticleIndex>& particles,
                        const std::vector<Vec3>* rest, const std::vector<Vec3>& position,
                        const std::vector<Vec3>& velocity) {
  RigidMotion m;
  Vec3 moment{};
  for (ParticleIndex i : particles) {
    m.mass += model.mass[i];
    moment += position[i] * model.mass[i];
  }
  if (!(m.mass > 0.0)) return m;
  m.center = moment / m.mass;
  Matrix33 inertia{}, a{};
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const ParticleIndex i = particles[k];
    const double w = model.mass[i];
    const Vec3 s = position[i] - m.center;
    const double ss = dot(s, s);
    const double c[3] = {s.x, s.y, s.z};
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) inertia[r][q] += w * ((r == q ? ss : 0.0) - c[r] * c[q]);
    if (rest != nullptr) {
      const Vec3& x = (*rest)[k];
      const double e[3] = {x.x, x.y, x.z};
      for (int r = 0; r < 3; ++r)
        for (int q = 0; q < 3; ++q) a[r][q] += w * c[r] * e[q];
    }
  }
  // A body on a line has no inertia about it: a trace-relative floor keeps I invertible.
  const double floor = 1e-9 * (inertia[0][0] + inertia[1][1] + inertia[2][2]);
  for (int r = 0; r < 3; ++r) inertia[r][r] += floor;
  const auto& t = inertia;
  const double det = t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) -
                     t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
                     t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0]);
  if (!(det > 0.0) || !std::isfinite(det)) return m;
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) {
      const int r1 = (q + 1) % 3, r2 = (q + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      m.inverseInertia[r][q] = (t[r1][c1] * t[r2][c2] - t[r1][c2] * t[r2][c1]) / det;
    }
  measureVelocity(model, particles, position, velocity, m);
  if (rest != nullptr) m.rotation = rotationOf(a);
  m.valid = true;
  return m;
}

void applyWrench(const Model& model, const std::vector<ParticleIndex>& particles,
                 const RigidMotion& m, const std::vector<Vec3>& position, const Vec3& f,
                 const Vec3& t, const Vec3& point, std::vector<Vec3>& force) {
  const Vec3 a = f / m.mass;
  const Vec3 alpha = m.solve(t + cross(point - m.center, f));
  for (ParticleIndex i : particles)
    force[i] += (a + cross(alpha, position[i] - m.center)) * model.mass[i];
}

void bodyMotions(const Model& model, const std::vector<Vec3>& position,
                 const std::vector<Vec3>& velocity, std::vector<RigidMotion>& out) {
  out.clear();
  out.reserve(model.bodies.size());
  for (const RigidGroup& body : model.bodies)
    out.push_back(rigidMotion(model, body.particles, &body.rest, position, velocity));
}

void updateBodyVelocities(const Model& model, const std::vector<Vec3>& position,
                          const std::vector<Vec3>& velocity, std::vector<RigidMotion>& motion) {
  for (std::size_t b = 0; b < std::min(motion.size(), model.bodies.size()); ++b)
    if (motion[b].valid)
      measureVelocity(model, model.bodies[b].particles, position, velocity, motion[b]);
}

BodyLinkFrame bodyLinkFrame(const BodyLink& link, const RigidMotion& child,
                            const RigidMotion& parent) {
  BodyLinkFrame f;
  f.childPoint = child.center + child.rotate(link.pointInChild);
  f.parentPoint = parent.center + parent.rotate(link.pointInParent);
  f.childAxis = child.rotate(link.axisInChild);
  f.parentAxis = parent.rotate(link.axisInParent);
  f.childNormal = child.rotate(link.normalInChild);
  f.parentNormal = parent.rotate(link.normalInParent);
  return f;
}

namespace {

// MODEL §1.7, the weight preload: the wrench (F, T) on the child at its joint point that
// holds the link's weight bodies against gravity, F = −Σ M_b g, T = −Σ (p̄_b − s_c) × M_b g,
// less its part along the link's free direction n_p (revolute: T's, prismatic: F's).
std::array<Vec3, 2> weightPreload(const Model& model, const BodyLink& link,
                                  const std::vector<RigidMotion>& motion, const BodyLinkFrame& f) {
  double mass = 0.0;
  Vec3 moment{};
  for (std::int32_t b : link.weightBodies) {
    const RigidMotion& m = motion[static_cast<std::size_t>(b)];
    mass += m.mass;
    moment += m.center * m.mass;
  }
  if (!(mass > 0.0)) return {Vec3{}, Vec3{}};
  const Vec3 weight = model.gravity * mass;
  Vec3 pull = weight * -1.0;
  Vec3 twist = cross(moment / mass - f.childPoint, weight) * -1.0;
  if (link.kind == BodyLinkKind::kRevolute) twist -= f.parentAxis * dot(f.parentAxis, twist);
  if (link.kind == BodyLinkKind::kPrismatic) pull -= f.parentAxis * dot(f.parentAxis, pull);
  return {pull, twist};
}

}  // namespace

double bodyLinkPreloadPower(const Model& model, const std::vector<RigidMotion>& motion,
                            const std::vector<std::array<Vec3, 2>>& preload) {
  double power = 0.0;
  const std::size_t count = std::min(model.bodyLinks.size(), preload.size());
  for (std::size_t k = 0; k < count; ++k) {
    const BodyLink& link = model.bodyLinks[k];
    if (link.weightBodies.empty()) continue;
    const RigidMotion& child = motion[static_cast<std::size_t>(link.child)];
    const RigidMotion& parent = motion[static_cast<std::size_t>(link.parent)];
    if (!child.valid || !parent.valid) continue;
    const Vec3 point = child.center + child.rotate(link.pointInChild);
    power += dot(preload[k][0], child.velocityAt(point) - parent.velocityAt(point)) +
             dot(preload[k][1], child.spin - parent.spin);
  }
  return power;
}

PowerKick rigidBodyPowerKick(const Model& model, const std::vector<RigidMotion>& motion,
                             const std::vector<RigidMotion>& kickMotion,
                             const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                             const std::vector<Vec3>& kick,
                             const std::vector<std::array<Vec3, 2>>& preload) {
  // accumulateRigidBodies' dampers, each force (at `velocity`) times the rate the
  // kick adds: the shape matching's −c m_i slip_i, the links' −c u and −c_a turnRate.
  PowerKick out;
  if (model.bodies.empty() || motion.size() != model.bodies.size() ||
      kickMotion.size() != model.bodies.size())
    return out;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const RigidGroup& body = model.bodies[b];
    const RigidMotion& m = motion[b];
    const RigidMotion& dm = kickMotion[b];
    if (!m.valid || body.frequency == 0.0) continue;
    const double c = 2.0 * body.dampingRatio * body.frequency;
    for (const ParticleIndex i : body.particles) {
      const Vec3 slip = velocity[i] - m.velocityAt(position[i]);
      const Vec3 kickSlip = kick[i] - dm.velocityAt(position[i]);
      out.dissipative -= model.mass[i] * c * dot(slip, kickSlip);
    }
  }
  for (std::size_t k = 0; k < model.bodyLinks.size(); ++k) {
    const BodyLink& link = model.bodyLinks[k];
    const auto ci = static_cast<std::size_t>(link.child);
    const auto pi = static_cast<std::size_t>(link.parent);
    if (!motion[ci].valid || !motion[pi].valid) continue;
    const BodyLinkFrame f = bodyLinkFrame(link, motion[ci], motion[pi]);
    Vec3 u = motion[ci].velocityAt(f.childPoint) - motion[pi].velocityAt(f.childPoint);
    Vec3 du = kickMotion[ci].velocityAt(f.childPoint) - kickMotion[pi].velocityAt(f.childPoint);
    if (link.kind == BodyLinkKind::kPrismatic) {
      u = u - f.parentAxis * dot(f.parentAxis, u);
      du = du - f.parentAxis * dot(f.parentAxis, du);
    }
    const Vec3 spin = motion[ci].spin - motion[pi].spin;
    const Vec3 kickSpin = kickMotion[ci].spin - kickMotion[pi].spin;
    Vec3 turnRate = spin - f.parentAxis * dot(f.parentAxis, spin);
    Vec3 kickTurnRate = kickSpin - f.parentAxis * dot(f.parentAxis, kickSpin);
    if (link.kind != BodyLinkKind::kRevolute) {
      turnRate = spin;
      kickTurnRate = kickSpin;
    }
    out.dissipative -=
        link.damping * dot(u, du) + link.angularDamping * dot(turnRate, kickTurnRate);
  }
  // The weight preloads are driving work (MODEL §1.7).
  if (preload.size() == model.bodyLinks.size() && !preload.empty())
    out.driving += bodyLinkPreloadPower(model, kickMotion, preload);
  return out;
}

ForceTally accumulateRigidBodies(const Model& model, const std::vector<RigidMotion>& motion,
                                 const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<std::array<Vec3, 2>>& preload) {
  ForceTally tally;
  preload.assign(model.bodyLinks.size(), {Vec3{}, Vec3{}});
  if (model.bodies.empty()) return tally;
  // Shape matching: f_i = m_i ω² (p̄ + R r_i − p_i) − 2ζω m_i (v_i − v_rigid(p_i)).
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const RigidGroup& body = model.bodies[b];
    const RigidMotion& m = motion[b];
    if (!m.valid || body.frequency == 0.0) continue;
    const double k = body.frequency * body.frequency;
    const double c = 2.0 * body.dampingRatio * body.frequency;
    for (std::size_t q = 0; q < body.particles.size(); ++q) {
      const ParticleIndex i = body.particles[q];
      const Vec3 gap = m.center + m.rotate(body.rest[q]) - position[i];
      const Vec3 slip = velocity[i] - m.velocityAt(position[i]);
      force[i] += (gap * k - slip * c) * model.mass[i];
      tally.potential += 0.5 * model.mass[i] * k * dot(gap, gap);
      tally.dissipativePower -= model.mass[i] * c * dot(slip, slip);
    }
  }
  // Body links: the penalty wrench on the child at its joint point, its reaction on the parent.
  for (std::size_t k = 0; k < model.bodyLinks.size(); ++k) {
    const BodyLink& link = model.bodyLinks[k];
    const RigidMotion& child = motion[static_cast<std::size_t>(link.child)];
    const RigidMotion& parent = motion[static_cast<std::size_t>(link.parent)];
    if (!child.valid || !parent.valid) continue;
    const BodyLinkFrame f = bodyLinkFrame(link, child, parent);
    Vec3 e = f.childPoint - f.parentPoint;
    Vec3 u = child.velocityAt(f.childPoint) - parent.velocityAt(f.childPoint);
    if (link.kind == BodyLinkKind::kPrismatic) {
      // Free along the parent's line.
      e = e - f.parentAxis * dot(f.parentAxis, e);
      u = u - f.parentAxis * dot(f.parentAxis, u);
    }
    const Vec3 spin = child.spin - parent.spin;
    Vec3 turn = cross(f.parentAxis, f.childAxis);
    Vec3 turnRate = spin - f.parentAxis * dot(f.parentAxis, spin);
    double misalignment = 1.0 - dot(f.parentAxis, f.childAxis);
    if (link.kind != BodyLinkKind::kRevolute) {
      // The roll about the axis locked too.
      turn += cross(f.parentNormal, f.childNormal);
      turnRate = spin;
      misalignment += 1.0 - dot(f.parentNormal, f.childNormal);
    }
    Vec3 pull = e * -link.stiffness - u * link.damping;
    Vec3 twist = turn * -link.angularStiffness - turnRate * link.angularDamping;
    if (!link.weightBodies.empty()) {
      preload[k] = weightPreload(model, link, motion, f);
      pull += preload[k][0];
      twist += preload[k][1];
    }
    applyWrench(model, model.bodies[static_cast<std::size_t>(link.child)].particles, child,
                position, pull, twist, f.childPoint, force);
    applyWrench(model, model.bodies[static_cast<std::size_t>(link.parent)].particles, parent,
                position, pull * -1.0, twist * -1.0, f.childPoint, force);
    tally.potential += 0.5 * link.stiffness * dot(e, e) + link.angularStiffness * misalignment;
    tally.dissipativePower -=
        link.damping * dot(u, u) + link.angularDamping * dot(turnRate, turnRate);
  }
  return tally;
}

}  // namespace robophi
