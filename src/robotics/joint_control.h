#pragma once
/// \file
/// Joint control between steps (MODEL §1 "Joint drive and passive joints"):
/// servo targets, stiffness and damping, switching a joint off, limits. These
/// change the World's model through its edit API: call them between steps.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/tasks.h"
#include "robophi/joints.h"
#include "robophi/world.h"

namespace robophi::robotics {

// The limit spec is plain data of the build layer (robophi/build/tasks.h).
using build::JointLimitSpec;

/// The joint lookup by name is the core's (robophi/joints.h).
using robophi::findJoint;

/// Drives the joint to `target` (rad, wrapped into [0, 2π), or m > 0): sets the
/// JS rest angle or the drive LS rest length. Returns false for a prismatic
/// joint without a drive.
bool setJointTarget(World& world, std::size_t joint, double target);
/// Sets the servo's stiffness (N·m/rad or N/m) and damping (N·m·s/rad or N·s/m).
bool setJointStiffness(World& world, std::size_t joint, double stiffness, double damping);
/// Switches the joint off (passive, MODEL §1): stiffness 0, small `damping`.
bool switchOffJoint(World& world, std::size_t joint, double damping);

/// Keeps joints within their limits: after each step, a joint outside
/// [min, max] becomes a stiff servo to the violated bound; once back inside, its
/// own servo settings are restored. One per scene or robot.
class JointLimiter {
 public:
  explicit JointLimiter(std::vector<JointLimitSpec> limits);
  /// Checks every limit against the world's state and updates the servos.
  void update(World& world);
  /// Whether limit `i` is holding its joint now.
  bool active(std::size_t i) const { return active_[i]; }
  /// How many times a limit engaged so far.
  int engagements() const { return engagements_; }
  /// Its state for a checkpoint, and back (robotics/task.h).
  nlohmann::json save() const;
  void restore(const nlohmann::json& saved);

 private:
  std::vector<JointLimitSpec> limits_;
  std::vector<bool> active_;
  std::vector<JointServo> saved_;
  int engagements_ = 0;
};

}  // namespace robophi::robotics
