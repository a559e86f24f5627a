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

/// The joint's value: rad in [0, 2π) for a revolute joint, m for a prismatic one; a
/// rigid tree's joint (Joint::inTree): its coordinate q itself (rad, not wrapped, or m).
/// Throws std::out_of_range for a joint that does not exist, std::invalid_argument
/// for a state not sized for the model.
double jointValue(const Model& model, const State& state, std::size_t joint);

/// The joint's position q, counted from Joint::zero: rad in (-π, π] for a revolute
/// joint (jointValue − zero, wrapped), m for a prismatic one (jointValue − zero); a
/// rigid tree's joint: its coordinate q, not wrapped (a joint may turn past ±π).
/// Same checks as jointValue.
double jointPosition(const Model& model, const State& state, std::size_t joint);

/// The raw value (jointValue's: rad in [0, 2π), or m) of position q (rad or m).
double jointRawValue(const Joint& joint, double position);

/// An angle wrapped into (-π, π] (rad).
double wrapSigned(double angle);

/// The joint's rate: rad/s or m/s (also the rate of its position). Same checks as jointValue.
double jointRate(const Model& model, const State& state, std::size_t joint);

/// The effort (N·m or N; positive increases q) the joint's servo applies at the
/// state (MODEL §1.5): −(κ Δθ + μ θ̇) of its JS, or −(κ Δl + μ l̇) of a prismatic
/// joint's drive LS (0 without one); a joint limit's servo included. Same checks
/// as jointValue.
double jointServoEffort(const Model& model, const State& state, std::size_t joint);

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
