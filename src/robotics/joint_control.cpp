// Joint control between steps: servo targets, stiffness, passive joints, limits
// (MODEL §1). Uses the public API only: World::mutableModel and jointValue.
#include "robotics/joint_control.h"

#include <cmath>

namespace robophi::robotics {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

double wrapTwoPi(double angle) {
  double wrapped = std::fmod(angle, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  return wrapped >= kTwoPi ? 0.0 : wrapped;
}

// Signed distance from `from` to `to` the short way round, in (-π, π].
double angleBetween(double from, double to) {
  double d = std::fmod(to - from, kTwoPi);
  if (d > M_PI) d -= kTwoPi;
  if (d <= -M_PI) d += kTwoPi;
  return d;
}

}  // namespace

std::optional<std::size_t> findJoint(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.joints.size(); ++i)
    if (model.joints[i].name == name) return i;
  return std::nullopt;
}

JointServo jointServo(const Model& model, std::size_t joint) {
  const Joint& j = model.joints[joint];
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[static_cast<std::size_t>(j.connector)];
    return {true, s.restAngle, s.stiffness, s.damping};
  }
  if (j.driveSpring < 0) return {false, 0.0, 0.0, 0.0};
  const LinearSpring& s = model.linearSprings[static_cast<std::size_t>(j.driveSpring)];
  return {true, s.restLength, s.stiffness, s.damping};
}

bool setJointTarget(World& world, std::size_t joint, double target) {
  Model& model = world.mutableModel();
  const Joint& j = model.joints[joint];
  if (j.kind == JointKind::kRevolute) {
    model.jointSprings[static_cast<std::size_t>(j.connector)].restAngle = wrapTwoPi(target);
    return true;
  }
  if (j.driveSpring < 0 || !(target > 0.0)) return false;
  model.linearSprings[static_cast<std::size_t>(j.driveSpring)].restLength = target;
  return true;
}

bool setJointStiffness(World& world, std::size_t joint, double stiffness, double damping) {
  Model& model = world.mutableModel();
  const Joint& j = model.joints[joint];
  if (j.kind == JointKind::kRevolute) {
    JointSpring& s = model.jointSprings[static_cast<std::size_t>(j.connector)];
    s.stiffness = stiffness;
    s.damping = damping;
    return true;
  }
  if (j.driveSpring < 0) return false;
  LinearSpring& s = model.linearSprings[static_cast<std::size_t>(j.driveSpring)];
  s.stiffness = stiffness;
  s.damping = damping;
  return true;
}

bool switchOffJoint(World& world, std::size_t joint, double damping) {
  return setJointStiffness(world, joint, 0.0, damping);
}

JointLimiter::JointLimiter(std::vector<JointLimitSpec> limits)
    : limits_(std::move(limits)), active_(limits_.size(), false), saved_(limits_.size()) {}

void JointLimiter::update(World& world) {
  for (std::size_t i = 0; i < limits_.size(); ++i) {
    const JointLimitSpec& limit = limits_[i];
    const Model& model = world.model();
    const bool revolute = model.joints[limit.joint].kind == JointKind::kRevolute;
    const double value = jointValue(model, world.state(), limit.joint);
    // Outside [min, max]; an angular range with min > max wraps through 0. The
    // bound to hold is the nearer one (for an angle, the short way round).
    bool outside = value < limit.min || value > limit.max;
    if (revolute && limit.min > limit.max) outside = value < limit.min && value > limit.max;
    const double toMin = revolute ? std::abs(angleBetween(value, limit.min)) : limit.min - value;
    const double toMax = revolute ? std::abs(angleBetween(value, limit.max)) : value - limit.max;
    if (outside) {
      const double bound = (revolute ? toMin <= toMax : toMin > 0.0) ? limit.min : limit.max;
      if (!active_[i]) {
        saved_[i] = jointServo(model, limit.joint);
        active_[i] = true;
        ++engagements_;
      }
      // The limit is the stiff one: never weaker than the joint's own servo.
      setJointStiffness(world, limit.joint, std::max(limit.stiffness, saved_[i].stiffness),
                        std::max(limit.damping, saved_[i].damping));
      setJointTarget(world, limit.joint, bound);
    } else if (active_[i]) {
      active_[i] = false;
      setJointStiffness(world, limit.joint, saved_[i].stiffness, saved_[i].damping);
      setJointTarget(world, limit.joint, saved_[i].target);
    }
  }
}

}  // namespace robophi::robotics
