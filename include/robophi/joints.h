#pragma once
/// \file
/// Reading named joints (MODEL §1: a joint's value is θ for a revolute joint,
/// the slider's distance along its line for a prismatic one).

#include <cstddef>
#include <optional>
#include <string>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// The joint's value: rad in [0, 2π) for a revolute joint, m for a prismatic one.
/// Throws std::out_of_range for a joint that does not exist, std::invalid_argument
/// for a state not sized for the model.
double jointValue(const Model& model, const State& state, std::size_t joint);

/// The joint's rate: rad/s or m/s. Same checks as jointValue.
double jointRate(const Model& model, const State& state, std::size_t joint);

/// An angle wrapped into [0, 2π) (rad): a revolute joint's value and target range.
double wrapAngle(double angle);

/// The index of the joint named `name` in Model::joints, or nullopt.
std::optional<std::size_t> findJoint(const Model& model, const std::string& name);

/// The servo parameters of a joint (MODEL §1): target (rad or m), stiffness,
/// damping. For a revolute joint they are its JS's; for a prismatic joint its
/// drive LS's (a prismatic joint without a drive has none: `hasDrive` false).
struct JointServo {
  bool hasDrive = true;
  double target = 0.0, stiffness = 0.0, damping = 0.0;
};
/// Throws std::out_of_range for a joint that does not exist.
JointServo jointServo(const Model& model, std::size_t joint);

}  // namespace robophi
