// Joint motors and losses (MODEL §1.6): a generalized force on a joint's
// position q, applied through the joint's own connector particles as
// F_j = Q ∂q/∂p_j, so that forces sum to zero and torques balance; or, for a
// joint with bodies (MODEL §1.7), as a wrench spread over its two bodies.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "forces/forces.h"
#include "robophi/connector_forces.h"
#include "robophi/joints.h"

namespace robophi {

namespace {

// The joint's particles in the order CoordinateGradient names them (a, c, b, d);
// d is kNoParticle for a prismatic joint.
struct JointParticles {
  ParticleIndex a = kNoParticle, c = kNoParticle, b = kNoParticle, d = kNoParticle;
};

JointParticles jointParticles(const Model& model, const Joint& joint) {
  if (joint.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[static_cast<std::size_t>(joint.connector)];
    return {s.a, s.c, s.b, s.d};
  }
  const TorsionSpring& s = model.torsionSprings[static_cast<std::size_t>(joint.connector)];
  return {s.a, s.c, s.b, kNoParticle};
}

// The gradient a drive acts through: h ∂q/∂p (MODEL §1.3, §1.6), bounded where an
// arm leans onto a revolute joint's axis; its rate is then h q̇, so that the
// drive's power is Q times that rate.
CoordinateGradient weighted(CoordinateGradient g) {
  if (g.weight != 1.0) {
    g.a = g.a * g.weight;
    g.c = g.c * g.weight;
    g.b = g.b * g.weight;
    g.d = g.d * g.weight;
  }
  return g;
}

CoordinateGradient gradientOf(const JointParticles& j, JointKind kind, const std::vector<Vec3>& p) {
  if (kind == JointKind::kRevolute)
    return weighted(jointAngleGradient(p[j.a], p[j.c], p[j.b], p[j.d]));
  return prismaticGradient(p[j.a], p[j.c], p[j.b]);
}

double rateOf(const CoordinateGradient& g, const JointParticles& j, const std::vector<Vec3>& v) {
  const Vec3 vD = j.d == kNoParticle ? Vec3{} : v[j.d];
  return g.rate(v[j.a], v[j.c], v[j.b], vD);
}

}  // namespace

bool hasDrive(const JointDrive& d) {
  return d.effort != 0.0 || d.rateGain != 0.0 || d.damping != 0.0 || d.friction != 0.0;
}

double motorEffort(const JointDrive& d, double rate) {
  // MODEL §1.6: τ = clamp(τ0 + k_v (q̇* − q̇), ±τ_max); none that drives |q̇| past the limit.
  double effort = d.effort + d.rateGain * (d.targetRate - rate);
  effort = std::clamp(effort, -d.effortLimit, d.effortLimit);
  if ((rate >= d.velocityLimit && effort > 0.0) || (rate <= -d.velocityLimit && effort < 0.0))
    effort = 0.0;
  return effort;
}

double lossEffort(const JointDrive& d, double rate) {
  // MODEL §1.6: −b q̇ − F_c clamp(q̇ / v_f, −1, 1).
  return -d.damping * rate - d.friction * std::clamp(rate / d.frictionVelocity, -1.0, 1.0);
}

namespace {

// MODEL §1.6: the drive's coordinate and rate — the JS's own, or, with motor
// particles, the mean over the child arms b and b_k (a rigid child turns them all
// alike) — and, per arm, its gradient.
struct DriveGeometry {
  bool valid = false;
  double rate = 0.0;
  std::vector<CoordinateGradient> arms;
  std::vector<ParticleIndex> child;  // each arm's child particle: b, then the motor particles
};

DriveGeometry driveGeometry(const Model& model, const Joint& joint, const JointParticles& j,
                            const std::vector<Vec3>& position, const std::vector<Vec3>& velocity) {
  DriveGeometry out;
  const CoordinateGradient g = gradientOf(j, joint.kind, position);
  if (!g.valid) return out;
  out.arms.push_back(g);
  out.child.push_back(j.b);
  double rateSum = rateOf(g, j, velocity);
  for (ParticleIndex b : joint.motorParticles) {
    const CoordinateGradient k =
        weighted(jointAngleGradient(position[j.a], position[j.c], position[b], position[j.d]));
    if (!k.valid) continue;
    out.arms.push_back(k);
    out.child.push_back(b);
    rateSum += k.rate(velocity[j.a], velocity[j.c], velocity[b], velocity[j.d]);
  }
  (void)model;
  out.rate = rateSum / static_cast<double>(out.arms.size());
  out.valid = true;
  return out;
}

// Adds Q ∂q/∂p over the arms, Q shared equally among them.
void applyDrive(const JointParticles& j, const DriveGeometry& g, double q,
                std::vector<Vec3>& force) {
  const double share = q / static_cast<double>(g.arms.size());
  for (std::size_t k = 0; k < g.arms.size(); ++k) {
    const CoordinateGradient& arm = g.arms[k];
    const ParticleIndex b = g.child[k];
    force[j.a] += arm.a * share;
    force[j.c] += arm.c * share;
    force[b] += arm.b * share;
    if (j.d != kNoParticle) force[j.d] += arm.d * share;
  }
}

// The drive's damping: d(−Q)/dq̇ of its rate gain, viscous damping and the
// viscous part of its friction (N·m·s/rad or N·s/m).
double driveDamping(const JointDrive& d) {
  return d.rateGain + d.damping + (d.friction > 0.0 ? d.friction / d.frictionVelocity : 0.0);
}

// One particle's weight in a drive's damping (driveDampingRate):
// w = √(g / m_p) |Ḡ_p|, Ḡ the drive's gradient ∂q̇/∂v (its arms' mean).
struct DriveWeight {
  ParticleIndex particle;
  std::int32_t drive;
  double weight;
};

void addDriveWeights(const Model& model, std::int32_t drive, double g, const JointParticles& j,
                     const DriveGeometry& geometry, std::vector<DriveWeight>& out) {
  const double share = 1.0 / static_cast<double>(geometry.arms.size());
  Vec3 onA, onC, onD;
  for (const CoordinateGradient& arm : geometry.arms) {
    onA += arm.a;
    onC += arm.c;
    onD += arm.d;
  }
  const auto add = [&](ParticleIndex p, const Vec3& gradient) {
    if (p == kNoParticle || model.inverseMass[p] == 0.0) return;
    out.push_back({p, drive, std::sqrt(g * model.inverseMass[p]) * norm(gradient)});
  };
  add(j.a, onA * share);
  add(j.c, onC * share);
  add(j.d, onD * share);
  for (std::size_t k = 0; k < geometry.arms.size(); ++k)
    add(geometry.child[k], geometry.arms[k].b * share);
}

// MODEL §4 (docs/adaptive-step.md): a bound on the largest rate (1/s) of M⁻¹ Σ_d g_d Ḡ_d Ḡ_dᵀ,
// the drives' damping. Its nonzero eigenvalues are the Gram matrix's,
// G_de = Σ_p √(g_d g_e / m_p²) Ḡ_d,p·Ḡ_e,p; by Gershgorin on G and |Ḡ_d,p·Ḡ_e,p| <=
// |Ḡ_d,p| |Ḡ_e,p|, every one is at most max_d Σ_p w_d,p W_p, W_p = Σ_e w_e,p: exactly
// g Σ_p |Ḡ_p|² / m_p for a drive that shares no particle with another.
double driveDampingBound(std::vector<DriveWeight>& weights) {
  if (weights.empty()) return 0.0;
  std::sort(weights.begin(), weights.end(), [](const DriveWeight& x, const DriveWeight& y) {
    return x.particle != y.particle ? x.particle < y.particle : x.drive < y.drive;
  });
  thread_local std::vector<std::pair<std::int32_t, double>> rows;  // (drive, its row sum)
  rows.clear();
  std::size_t first = 0;
  while (first < weights.size()) {
    std::size_t last = first;
    double column = 0.0;
    while (last < weights.size() && weights[last].particle == weights[first].particle)
      column += weights[last++].weight;
    for (std::size_t k = first; k < last; ++k)
      rows.emplace_back(weights[k].drive, weights[k].weight * column);
    first = last;
  }
  std::sort(rows.begin(), rows.end());
  double largest = 0.0;
  for (std::size_t k = 0; k < rows.size();) {
    double sum = 0.0;
    const std::int32_t drive = rows[k].first;
    for (; k < rows.size() && rows[k].first == drive; ++k) sum += rows[k].second;
    largest = std::max(largest, sum);
  }
  return largest;
}

}  // namespace

namespace {

// A body-driven joint (MODEL §1.7): its axis (the parent's, unit), its point (the
// child's joint point), the bodies' rigid motions and the rate q̇.
struct BodyJoint {
  bool valid = false;
  Vec3 axis{}, point{};
  const RigidMotion* child = nullptr;
  const RigidMotion* parent = nullptr;
  const std::vector<ParticleIndex>* childParticles = nullptr;
  const std::vector<ParticleIndex>* parentParticles = nullptr;
  BodyLinkFrame frame{};
  double rate = 0.0;  // rad/s or m/s
};

// The joint's bodies taken from `motion` (every body's rigid motion: bodyMotions).
BodyJoint bodyJoint(const Model& model, const Joint& joint,
                    const std::vector<RigidMotion>& motion) {
  BodyJoint out;
  const BodyLink& link = model.bodyLinks[static_cast<std::size_t>(joint.bodyLink)];
  const auto childIndex = static_cast<std::size_t>(link.child);
  const auto parentIndex = static_cast<std::size_t>(link.parent);
  if (childIndex >= motion.size() || parentIndex >= motion.size()) return out;
  out.child = &motion[childIndex];
  out.parent = &motion[parentIndex];
  if (!out.child->valid || !out.parent->valid) return out;
  out.childParticles = &model.bodies[childIndex].particles;
  out.parentParticles = &model.bodies[parentIndex].particles;
  const BodyLinkFrame f = bodyLinkFrame(link, *out.child, *out.parent);
  out.frame = f;
  out.axis = f.parentAxis;
  out.point = f.childPoint;
  out.rate =
      joint.kind == JointKind::kRevolute
          ? dot(out.axis, out.child->spin - out.parent->spin)
          : dot(out.axis, out.child->velocityAt(out.point) - out.parent->velocityAt(out.point));
  out.valid = true;
  return out;
}

// Applies the generalized force Q: +wrench on the child, −wrench on the parent.
void applyBodyEffort(const Model& model, const Joint& joint, const BodyJoint& b,
                     const std::vector<Vec3>& position, double q, std::vector<Vec3>& force) {
  const bool revolute = joint.kind == JointKind::kRevolute;
  const Vec3 f = revolute ? Vec3{} : b.axis * q;
  const Vec3 t = revolute ? b.axis * q : Vec3{};
  applyWrench(model, *b.childParticles, *b.child, position, f, t, b.point, force);
  applyWrench(model, *b.parentParticles, *b.parent, position, f * -1.0, t * -1.0, b.point, force);
}

// The body servo's position error (rad, wrapped; or m), measured on the bodies as their
// rate is: the raw value as built (the JS's rest angle, the drive LS's rest length) plus
// the bodies' turn about n_p since (the angle from the parent's normal to the child's) or
// their slide along it. Not the JS's own particles: a particle that the contacts or the
// lattice move off its body's rigid motion would feed the servo an error the bodies do
// not have (R2D2's wheels: a rim particle pushed by the ground spun the wheel).
double servoError(const Model& model, const Joint& joint, const BodyJoint& b) {
  const BodyLinkFrame& f = b.frame;
  if (joint.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[static_cast<std::size_t>(joint.connector)];
    const double turn = std::atan2(dot(f.parentAxis, cross(f.parentNormal, f.childNormal)),
                                   dot(f.parentNormal, f.childNormal));
    return wrapSigned(s.restAngle + turn - joint.servoTarget);
  }
  const double built =
      joint.driveSpring >= 0
          ? model.linearSprings[static_cast<std::size_t>(joint.driveSpring)].restLength
          : 0.0;
  return built + dot(f.parentAxis, f.childPoint - f.parentPoint) - joint.servoTarget;
}

// Minus gravity's generalized force on the joint's subtree (Joint::subtreeBodies):
// revolute, −n·Σ (p̄_b − s) × M_b g; prismatic, −n·Σ M_b g.
double gravityEffort(const Model& model, const Joint& joint, const BodyJoint& b,
                     const std::vector<Vec3>& position) {
  double mass = 0.0;
  Vec3 moment{};
  for (std::int32_t body : joint.subtreeBodies)
    for (ParticleIndex i : model.bodies[static_cast<std::size_t>(body)].particles) {
      if (model.inverseMass[i] == 0.0) continue;
      mass += model.mass[i];
      moment += position[i] * model.mass[i];
    }
  if (!(mass > 0.0)) return 0.0;
  const Vec3 weight = model.gravity * mass;
  if (joint.kind == JointKind::kRevolute)
    return -dot(b.axis, cross(moment / mass - b.point, weight));
  return -dot(b.axis, weight);
}

bool hasBodyServo(const Joint& joint) {
  return joint.servoStiffness != 0.0 || joint.servoDamping != 0.0;
}

}  // namespace

double bodyServoEffort(const Model& model, const Joint& joint, const std::vector<Vec3>& position,
                       const std::vector<Vec3>& velocity) {
  if (!joint.actsThroughBodies() || !hasBodyServo(joint)) return 0.0;
  const BodyLink& link = model.bodyLinks[static_cast<std::size_t>(joint.bodyLink)];
  std::vector<RigidMotion> motion(model.bodies.size());
  for (const std::int32_t body : {link.child, link.parent}) {
    const RigidGroup& group = model.bodies[static_cast<std::size_t>(body)];
    motion[static_cast<std::size_t>(body)] =
        rigidMotion(model, group.particles, &group.rest, position, velocity);
  }
  const BodyJoint b = bodyJoint(model, joint, motion);
  if (!b.valid) return 0.0;
  return -joint.servoStiffness * servoError(model, joint, b) - joint.servoDamping * b.rate;
}

ForceTally accumulateJointDrives(const Model& model, const std::vector<RigidMotion>& motion,
                                 const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<double>& motor, std::vector<double>& loss,
                                 double* dampingRate) {
  ForceTally tally;
  const std::size_t count = model.joints.size();
  motor.assign(count, 0.0);
  loss.assign(count, 0.0);
  thread_local std::vector<DriveWeight> weights;
  weights.clear();
  for (std::size_t k = 0; k < count; ++k) {
    const Joint& joint = model.joints[k];
    if (joint.inTree()) continue;  // the tree's stage drives it (docs/model.md §7)
    if (joint.actsThroughBodies()) {
      const bool servo = hasBodyServo(joint);
      const bool compensate = joint.compensateGravity && !joint.subtreeBodies.empty();
      if (!servo && !compensate && !hasDrive(joint.drive)) continue;
      const BodyJoint b = bodyJoint(model, joint, motion);
      if (!b.valid) continue;
      double q = 0.0;
      if (hasDrive(joint.drive)) {
        motor[k] = motorEffort(joint.drive, b.rate);
        loss[k] = lossEffort(joint.drive, b.rate);
        q = motor[k] + loss[k];
        tally.dissipativePower += loss[k] * b.rate;
      }
      if (compensate) {
        // MODEL §1.7: the effort that holds the bodies below against gravity, a motor's.
        const double hold = gravityEffort(model, joint, b, position);
        motor[k] += hold;
        q += hold;
      }
      if (servo) {
        // MODEL §1.7: the spring's energy ½ κ e², the damper's power −β q̇².
        const double e = servoError(model, joint, b);
        q += -joint.servoStiffness * e - joint.servoDamping * b.rate;
        tally.potential += 0.5 * joint.servoStiffness * e * e;
        tally.dissipativePower -= joint.servoDamping * b.rate * b.rate;
      }
      applyBodyEffort(model, joint, b, position, q, force);
      continue;
    }
    if (!hasDrive(joint.drive)) continue;
    const JointParticles j = jointParticles(model, joint);
    const DriveGeometry g = driveGeometry(model, joint, j, position, velocity);
    if (!g.valid) continue;
    motor[k] = motorEffort(joint.drive, g.rate);
    loss[k] = lossEffort(joint.drive, g.rate);
    applyDrive(j, g, motor[k] + loss[k], force);
    tally.dissipativePower += loss[k] * g.rate;
    const double damping = driveDamping(joint.drive);
    if (dampingRate != nullptr && damping > 0.0)
      addDriveWeights(model, static_cast<std::int32_t>(k), damping, j, g, weights);
  }
  if (dampingRate != nullptr) *dampingRate = driveDampingBound(weights);
  return tally;
}

double jointMotorPower(const Model& model, const std::vector<RigidMotion>& motion,
                       const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                       const std::vector<double>& motor) {
  double power = 0.0;
  const std::size_t count = std::min(model.joints.size(), motor.size());
  for (std::size_t k = 0; k < count; ++k) {
    if (motor[k] == 0.0) continue;
    const Joint& joint = model.joints[k];
    if (joint.inTree()) continue;
    if (joint.actsThroughBodies()) {
      const BodyJoint b = bodyJoint(model, joint, motion);
      if (b.valid) power += motor[k] * b.rate;
      continue;
    }
    const JointParticles j = jointParticles(model, joint);
    const DriveGeometry g = driveGeometry(model, joint, j, position, velocity);
    if (g.valid) power += motor[k] * g.rate;
  }
  return power;
}

PowerKick verletKickPower(const Model& model, const std::vector<RigidMotion>& motion,
                          const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                          const std::vector<Vec3>& force, double halfStep,
                          const std::vector<double>& motor, const std::vector<double>& loss,
                          const std::vector<std::array<Vec3, 2>>& preload) {
  PowerKick out;
  const std::size_t count = std::min({model.joints.size(), motor.size(), loss.size()});
  bool any = !model.bodies.empty();
  for (std::size_t k = 0; k < count && !any; ++k) {
    const Joint& joint = model.joints[k];
    any = !joint.inTree() && (motor[k] != 0.0 || loss[k] != 0.0 ||
                              (joint.actsThroughBodies() && joint.servoDamping != 0.0));
  }
  if (!any) return out;
  // The kick's velocity change, and the bodies' rigid motion of it (rates are linear
  // in the velocities at fixed positions: q̇(v + δv) = q̇(v) + q̇(δv)).
  thread_local std::vector<Vec3> kick;
  thread_local std::vector<RigidMotion> kickMotion;
  const std::size_t n = position.size();
  kick.resize(n);
  for (std::size_t i = 0; i < n; ++i) kick[i] = force[i] * (model.inverseMass[i] * halfStep);
  kickMotion = motion;
  if (kickMotion.size() == model.bodies.size())
    updateBodyVelocities(model, position, kick, kickMotion);
  for (std::size_t k = 0; k < count; ++k) {
    const Joint& joint = model.joints[k];
    if (joint.inTree()) continue;
    if (joint.actsThroughBodies()) {
      const bool servoDamper = joint.servoDamping != 0.0;
      if (motor[k] == 0.0 && loss[k] == 0.0 && !servoDamper) continue;
      const BodyJoint b = bodyJoint(model, joint, motion);
      const BodyJoint dv = bodyJoint(model, joint, kickMotion);
      if (!b.valid || !dv.valid) continue;
      out.driving += motor[k] * dv.rate;
      out.dissipative += (loss[k] - joint.servoDamping * b.rate) * dv.rate;
      continue;
    }
    // A drive through connector particles keeps the trapezoid at u: past its damping
    // limit (Evaluation::driveDampingRate, warned for a constant step) its explicit
    // damping makes energy, and the account is what shows it (docs/model.md §2.4).
  }
  const PowerKick bodies =
      rigidBodyPowerKick(model, motion, kickMotion, position, velocity, kick, preload);
  out.driving += bodies.driving;
  out.dissipative += bodies.dissipative;
  return out;
}

}  // namespace robophi
