#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/text.h"
#include "forces/forces.h"
#include "robophi/connector_forces.h"
#include "robophi/joints.h"

namespace robophi {

namespace {

// Prismatic: the TS keeps origin (a), slider (c) and end (b) collinear; the
// value is the slider's distance from the origin along the origin→end line.
double prismaticValue(const TorsionSpring& s, const std::vector<Vec3>& p) {
  const Vec3 line = p[s.b] - p[s.a];
  const double length = norm(line);
  if (!(length > 0.0)) return norm(p[s.c] - p[s.a]);
  return dot(p[s.c] - p[s.a], line / length);
}

// Throws unless `joint` exists and `state` is sized for `model`.
const Joint& checkedJoint(const char* function, const Model& model, const State* state,
                          std::size_t joint) {
  if (joint >= model.joints.size())
    throw std::out_of_range(detail::text("{}: joint {} does not exist (the model has {})", function,
                                         joint, model.joints.size()));
  const auto n = static_cast<std::size_t>(model.particleCount());
  if (state != nullptr && (state->position.size() != n || state->velocity.size() != n))
    throw std::invalid_argument(
        detail::text("{}: the state has {} positions; the model has {} particles", function,
                     state->position.size(), n));
  return model.joints[joint];
}

// A tree joint's body (docs/model.md §7), and its coordinate and rate.
const MultibodyBody& treeBodyOf(const Model& model, const Joint& j) {
  return model.rigidTrees[static_cast<std::size_t>(j.tree)]
      .multibody.bodies[static_cast<std::size_t>(j.treeBody)];
}
double treeCoordinate(const Model& model, const State& state, const Joint& j) {
  return state.treePositions[static_cast<std::size_t>(j.tree)]
                            [static_cast<std::size_t>(treeBodyOf(model, j).qStart)];
}
double treeRate(const Model& model, const State& state, const Joint& j) {
  return state.treeVelocities[static_cast<std::size_t>(j.tree)]
                             [static_cast<std::size_t>(treeBodyOf(model, j).vStart)];
}

}  // namespace

double treeJointEffort(const Model& model, const Joint& joint, double q, double rate) {
  const MultibodyBody& body = treeBodyOf(model, joint);
  const double servo =
      -joint.servoStiffness * (q - joint.servoTarget) - joint.servoDamping * rate;
  const double drive = motorEffort(joint.drive, rate) + lossEffort(joint.drive, rate);
  return std::clamp(servo + drive, -body.effortLimit, body.effortLimit);
}

double jointValue(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = checkedJoint("jointValue", model, &state, joint);
  if (j.inTree()) return treeCoordinate(model, state, j);
  const auto& p = state.position;
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[j.connector];
    return jointAngle(p[s.a], p[s.c], p[s.b], p[s.d]);
  }
  return prismaticValue(model.torsionSprings[j.connector], p);
}

double jointPosition(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = checkedJoint("jointPosition", model, &state, joint);
  const double value = jointValue(model, state, joint);
  return j.wraps() ? wrapSigned(value - j.zero) : value - j.zero;
}

double jointRawValue(const Joint& joint, double position) {
  return joint.wraps() ? wrapAngle(joint.zero + position) : joint.zero + position;
}

double jointRate(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = checkedJoint("jointRate", model, &state, joint);
  if (j.inTree()) return treeRate(model, state, j);
  const auto& p = state.position;
  const auto& v = state.velocity;
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[j.connector];
    return jointAngleRate(p[s.a], p[s.c], p[s.b], p[s.d], v[s.a], v[s.c], v[s.b], v[s.d]);
  }
  const TorsionSpring& s = model.torsionSprings[j.connector];
  const Vec3 line = p[s.b] - p[s.a];
  const double length = norm(line);
  if (!(length > 0.0)) return 0.0;
  return dot(v[s.c] - v[s.a], line / length);
}

double jointServoEffort(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = checkedJoint("jointServoEffort", model, &state, joint);
  const auto& p = state.position;
  const auto& v = state.velocity;
  if (j.inTree()) return treeJointEffort(model, j, treeCoordinate(model, state, j), treeRate(model, state, j));
  if (j.actsThroughBodies()) return bodyServoEffort(model, j, p, v);
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[static_cast<std::size_t>(j.connector)];
    const double angle = jointAngle(p[s.a], p[s.c], p[s.b], p[s.d]);
    const double rate =
        jointAngleRate(p[s.a], p[s.c], p[s.b], p[s.d], v[s.a], v[s.c], v[s.b], v[s.d]);
    return -(s.stiffness * wrapSigned(angle - s.restAngle) + s.damping * rate);
  }
  if (j.driveSpring < 0) return 0.0;
  // The drive LS from the origin to the slider pulls along q (MODEL §1.4).
  const LinearSpring& s = model.linearSprings[static_cast<std::size_t>(j.driveSpring)];
  const Vec3 d = p[s.b] - p[s.a];
  const double length = norm(d);
  if (!(length > 0.0)) return 0.0;
  const double stretchRate = dot(v[s.b] - v[s.a], d * (1.0 / length));
  return -(s.stiffness * (length - s.restLength) + s.damping * stretchRate);
}

}  // namespace robophi

namespace robophi {

double wrapAngle(double angle) {
  const double twoPi = 2.0 * std::numbers::pi;
  double wrapped = std::fmod(angle, twoPi);
  if (wrapped < 0.0) wrapped += twoPi;
  if (wrapped >= twoPi) wrapped = 0.0;
  return wrapped;
}

double wrapSigned(double angle) {
  const double pi = std::numbers::pi;
  const double wrapped = wrapAngle(angle);  // [0, 2π)
  return wrapped > pi ? wrapped - 2.0 * pi : wrapped;
}

std::optional<std::size_t> findJoint(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.joints.size(); ++i)
    if (model.joints[i].name == name) return i;
  return std::nullopt;
}

JointServo jointServo(const Model& model, std::size_t joint) {
  const Joint& j = checkedJoint("jointServo", model, nullptr, joint);
  if (j.actsThroughBodies() || j.inTree()) return {true, j.servoTarget, j.servoStiffness, j.servoDamping};
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[static_cast<std::size_t>(j.connector)];
    return {true, s.restAngle, s.stiffness, s.damping};
  }
  if (j.driveSpring < 0) return {false, 0.0, 0.0, 0.0};
  const LinearSpring& s = model.linearSprings[static_cast<std::size_t>(j.driveSpring)];
  return {true, s.restLength, s.stiffness, s.damping};
}

}  // namespace robophi
