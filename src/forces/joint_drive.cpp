// Joint motors and losses (MODEL §1.6): a generalized force on a joint's
// position q, applied through the joint's own connector particles as
// F_j = Q ∂q/∂p_j, so that forces sum to zero and torques balance.
#include <algorithm>
#include <cmath>
#include <vector>

#include "forces/forces.h"
#include "robophi/connector_forces.h"

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

CoordinateGradient gradientOf(const JointParticles& j, JointKind kind, const std::vector<Vec3>& p) {
  if (kind == JointKind::kRevolute) return jointAngleGradient(p[j.a], p[j.c], p[j.b], p[j.d]);
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
};

DriveGeometry driveGeometry(const Model& model, const Joint& joint, const JointParticles& j,
                            const std::vector<Vec3>& position, const std::vector<Vec3>& velocity) {
  DriveGeometry out;
  const CoordinateGradient g = gradientOf(j, joint.kind, position);
  if (!g.valid) return out;
  out.arms.push_back(g);
  double rateSum = rateOf(g, j, velocity);
  for (ParticleIndex b : joint.motorParticles) {
    const CoordinateGradient k =
        jointAngleGradient(position[j.a], position[j.c], position[b], position[j.d]);
    if (!k.valid) continue;
    out.arms.push_back(k);
    rateSum += k.rate(velocity[j.a], velocity[j.c], velocity[b], velocity[j.d]);
  }
  (void)model;
  out.rate = rateSum / static_cast<double>(out.arms.size());
  out.valid = true;
  return out;
}

// Adds Q ∂q/∂p over the arms, Q shared equally among them.
void applyDrive(const Joint& joint, const JointParticles& j, const DriveGeometry& g, double q,
                std::vector<Vec3>& force) {
  const double share = q / static_cast<double>(g.arms.size());
  for (std::size_t k = 0; k < g.arms.size(); ++k) {
    const CoordinateGradient& arm = g.arms[k];
    const ParticleIndex b = k == 0 ? j.b : joint.motorParticles[k - 1];
    force[j.a] += arm.a * share;
    force[j.c] += arm.c * share;
    force[b] += arm.b * share;
    if (j.d != kNoParticle) force[j.d] += arm.d * share;
  }
}

}  // namespace

ForceTally accumulateJointDrives(const Model& model, const std::vector<Vec3>& position,
                                 const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                 std::vector<double>& motor, std::vector<double>& loss) {
  ForceTally tally;
  const std::size_t count = model.joints.size();
  motor.assign(count, 0.0);
  loss.assign(count, 0.0);
  for (std::size_t k = 0; k < count; ++k) {
    const Joint& joint = model.joints[k];
    if (!hasDrive(joint.drive)) continue;
    const JointParticles j = jointParticles(model, joint);
    const DriveGeometry g = driveGeometry(model, joint, j, position, velocity);
    if (!g.valid) continue;
    motor[k] = motorEffort(joint.drive, g.rate);
    loss[k] = lossEffort(joint.drive, g.rate);
    applyDrive(joint, j, g, motor[k] + loss[k], force);
    tally.dissipativePower += loss[k] * g.rate;
  }
  return tally;
}

double jointMotorPower(const Model& model, const std::vector<Vec3>& position,
                       const std::vector<Vec3>& velocity, const std::vector<double>& motor) {
  double power = 0.0;
  const std::size_t count = std::min(model.joints.size(), motor.size());
  for (std::size_t k = 0; k < count; ++k) {
    if (motor[k] == 0.0) continue;
    const Joint& joint = model.joints[k];
    const JointParticles j = jointParticles(model, joint);
    const DriveGeometry g = driveGeometry(model, joint, j, position, velocity);
    if (g.valid) power += motor[k] * g.rate;
  }
  return power;
}

}  // namespace robophi
