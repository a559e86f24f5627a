// Joint control between steps: servo targets, stiffness, passive joints, limits
// (MODEL §1). Uses the public API only: World's edits and jointValue.
#include "robotics/joint_control.h"

#include <cmath>

#include "output/json_numbers.h"

namespace robophi::robotics {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

// Signed distance from `from` to `to` the short way round, in (-π, π].
double angleBetween(double from, double to) {
  double d = std::fmod(to - from, kTwoPi);
  if (d > M_PI) d -= kTwoPi;
  if (d <= -M_PI) d += kTwoPi;
  return d;
}

}  // namespace

bool setJointTarget(World& world, std::size_t joint, double target) {
  const Joint& j = world.model().joints.at(joint);
  if (!j.hasServo() || (j.driveSpring >= 0 && !(target > 0.0))) return false;
  world.setJointTarget(joint, target);
  return true;
}

bool setJointStiffness(World& world, std::size_t joint, double stiffness, double damping) {
  const Joint& j = world.model().joints.at(joint);
  if (!j.hasServo()) return false;
  world.setJointServo(joint, stiffness, damping);
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
    const bool revolute = model.joints[limit.joint].wraps();
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

nlohmann::json JointLimiter::save() const {
  auto servos = nlohmann::json::array();
  for (const JointServo& s : saved_) {
    servos.push_back({{"has_drive", s.hasDrive},
                      {"target", output::exactNumber(s.target)},
                      {"stiffness", output::exactNumber(s.stiffness)},
                      {"damping", output::exactNumber(s.damping)}});
  }
  std::vector<int> active(active_.begin(), active_.end());
  return {{"active", active}, {"saved", servos}, {"engagements", engagements_}};
}

void JointLimiter::restore(const nlohmann::json& saved) {
  const auto active = saved.at("active").get<std::vector<int>>();
  const auto& servos = saved.at("saved");
  if (active.size() != limits_.size() || servos.size() != limits_.size())
    throw std::runtime_error("joint limits: the checkpoint has another number of limits");
  for (std::size_t i = 0; i < limits_.size(); ++i) {
    active_[i] = active[i] != 0;
    const auto& s = servos[i];
    saved_[i] = JointServo{s.at("has_drive").get<bool>(),
                           output::numberFromJson(s.at("target"), "joint limit target"),
                           output::numberFromJson(s.at("stiffness"), "joint limit stiffness"),
                           output::numberFromJson(s.at("damping"), "joint limit damping")};
  }
  engagements_ = saved.at("engagements").get<int>();
}

}  // namespace robophi::robotics
