#pragma once
/// \file
/// Joint actuators and control sequences as plain data (docs/robots.md
/// "Controlling joints", MODEL §1.5, §1.6): per joint a mode (position,
/// velocity, effort) with gains, limits and a target that changes in time;
/// mimic joints; moving bases; a sequence of phases that start at a time, after
/// a delay or when a condition holds. The scene's "control" section and the
/// C++ API (robotics::Controller) fill it; nothing here runs in the step.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// How keyframes are interpolated.
enum class Interpolation : std::uint8_t {
  /// Piecewise linear.
  kLinear,
  /// Cubic Hermite with Catmull-Rom tangents (the slope between the two
  /// neighbouring keyframes; one-sided at the ends): C¹, passes through every
  /// keyframe (it may overshoot between them where the slope changes sign).
  kCubic,
};

/// A value that changes in time: constant, keyframes or a sine. Times are
/// counted from when the trajectory starts (its phase's start; 0 outside a
/// sequence). Units are the quantity's: rad or m for a position, rad/s or m/s
/// for a rate, N·m or N for an effort.
struct Trajectory {
  enum class Kind : std::uint8_t { kConstant, kKeyframes, kSine };
  Kind kind = Kind::kConstant;
  /// kConstant: the value.
  double value = 0.0;
  /// kKeyframes: increasing times (s, >= 0) and their values; before the first
  /// time the first value, after the last the last value (held).
  std::vector<double> times, values;
  Interpolation interpolation = Interpolation::kLinear;
  /// kSine: offset + amplitude sin(2π t / period + phase); period (s) > 0, phase (rad).
  double amplitude = 0.0, period = 1.0, phase = 0.0, offset = 0.0;

  static Trajectory constant(double v) {
    Trajectory t;
    t.value = v;
    return t;
  }
};

/// The trajectory's value and rate (per second) at time t (s) since it started.
double trajectoryValue(const Trajectory& trajectory, double t);
double trajectoryRate(const Trajectory& trajectory, double t);
/// Empty if the trajectory is valid, otherwise the problem (names the field).
std::string checkTrajectory(const Trajectory& trajectory);

/// What drives a joint.
enum class JointMode : std::uint8_t {
  /// Position servo (MODEL §1.5): the JS (or drive LS) with stiffness kp, damping
  /// kd and target q*(t); the motor adds kd q̇*(t) (so the damping acts on q̇* − q̇).
  kPosition,
  /// Rate drive (MODEL §1.6): motor effort kv (q̇*(t) − q̇); the servo switched off.
  kVelocity,
  /// Motor effort τ(t) (MODEL §1.6); the servo switched off.
  kEffort,
  /// Passive: servo and motor off (the losses stay).
  kPassive,
};

/// One joint's actuator.
struct ActuatorSpec {
  /// Index into Model::joints.
  std::size_t joint = 0;
  JointMode mode = JointMode::kPosition;
  /// Position gains: kp (N·m/rad or N/m) >= 0, kd (N·m·s/rad or N·s/m) >= 0.
  double kp = 0.0, kd = 0.0;
  /// Velocity gain kv (N·m·s/rad or N·s/m) >= 0.
  double kv = 0.0;
  /// The target: q* (rad or m, the joint's position q: 0 as built), q̇* (rad/s or
  /// m/s) or τ (N·m or N), by mode.
  Trajectory target{};
  /// Feed-forward effort (N·m or N) added in position and velocity mode.
  double feedForward = 0.0;
  /// Limits (N·m or N; rad/s or m/s), > 0; unset: the joint's own (JointDrive).
  /// In position mode the servo's target is kept within effortLimit / kp of q
  /// and moves at most at velocityLimit.
  std::optional<double> effortLimit{}, velocityLimit{};
  /// Losses (JointDrive::damping, friction), >= 0; unset: the joint's own.
  std::optional<double> damping{}, friction{};
};

/// Joint `joint` follows multiplier · q_leader + offset (a URDF mimic), by a
/// position servo of gains kp, kd.
struct MimicSpec {
  std::size_t joint = 0, leader = 0;
  double multiplier = 1.0, offset = 0.0;
  double kp = 0.0, kd = 0.0;
};

/// A moving base: particles (fixed ones: they move kinematically) carried
/// rigidly along a trajectory from where they were when the motion started: a
/// translation (m, one trajectory per axis) and a rotation by `angle` (rad)
/// about `axis` through their centroid (build::movedPose).
struct BaseMotionSpec {
  std::string name;
  std::vector<ParticleIndex> particles;
  /// x, y, z of the translation (m) in time since the motion started.
  std::array<Trajectory, 3> translation{};
  /// The rotation's axis (-, any length; zero: none) and angle (rad) in time.
  Vec3 axis{0.0, 0.0, 1.0};
  Trajectory angle{};
};

/// When a phase starts.
struct ConditionSpec {
  enum class Kind : std::uint8_t {
    /// At time `time` (s) of the run.
    kAt,
    /// `time` (s) after the previous phase started.
    kAfter,
    /// When the listed joints are each within `tolerance` (rad or m) of their
    /// position targets (the previous phase's; every position actuator if none listed).
    kJointsAtTarget,
    /// When the sum of the normal contact forces (N) between object `object`
    /// and object `other` (-1: anything else) exceeds `force`.
    kContactForce,
  };
  Kind kind = Kind::kAfter;
  double time = 0.0;
  std::vector<std::size_t> joints;
  double tolerance = 0.01;
  std::int32_t object = -1, other = -1;
  double force = 0.0;
  /// A condition still false `timeout` (s) after the previous phase started
  /// starts the phase anyway, and says so; <= 0: wait for ever.
  double timeout = 0.0;
};

/// A phase of a sequence: from its start, these actuators (replacing the
/// previous settings of their joints) and base motions apply; trajectories
/// count their time from the phase's start.
struct PhaseSpec {
  std::string name;
  ConditionSpec start{};
  std::vector<ActuatorSpec> actuators;
  std::vector<BaseMotionSpec> bases;
};

/// A model's control: actuators and bases from t = 0, mimic joints, and a
/// sequence of phases run in order.
struct ControlSpec {
  std::vector<ActuatorSpec> actuators;
  std::vector<MimicSpec> mimics;
  std::vector<BaseMotionSpec> bases;
  std::vector<PhaseSpec> phases;
  bool empty() const {
    return actuators.empty() && mimics.empty() && bases.empty() && phases.empty();
  }
};

/// A mount (docs/robots.md "Mounts"): object `object`'s fixed particles (a
/// robot's base) are freed and each tied by `links` stiff LS to the nearest
/// particles of object `on` (an arm on a vehicle), at their present distances.
struct MountSpec {
  std::int32_t object = -1, on = -1;
  /// LS stiffness (N/m), > 0, and damping (N·s/m), >= 0; unset: 0.2 √(κ m / 2),
  /// m the lighter particle's mass.
  double stiffness = 2.0e4;
  std::optional<double> damping{};
  /// LS per base particle, >= 1.
  int links = 4;
};

/// Applies a mount to a model: frees the base particles and adds the LS.
/// Throws std::invalid_argument naming the problem (objects missing or the
/// same, no fixed particle, too few particles to tie to).
void addMount(Model& model, const std::vector<Vec3>& position, const MountSpec& spec);

/// What an actuator asks of its joint at one moment: the servo (MODEL §1.5) and
/// the drive (MODEL §1.6). Units as ActuatorSpec's.
struct JointCommand {
  /// Servo stiffness and damping; 0 and 0 outside position mode.
  double stiffness = 0.0, damping = 0.0;
  /// The servo's target position q* (rad or m; position mode only), after the
  /// limits: within effortLimit / kp of q.
  double target = 0.0;
  /// The rate-limited target (velocity limit), before the effort clamp: the next
  /// command's `previousTarget`.
  double command = 0.0;
  /// The drive: the joint's current one with the mode's effort, rate gain and
  /// target rate, and the spec's limits and losses where it sets them.
  JointDrive drive{};
};

/// The command of actuator `a` at time t (s) since its trajectory started, for a
/// joint at position q (rad or m) whose drive is `current` (its limits and losses
/// stay unless the spec sets them). `previousTarget` (position mode): the last
/// command's `command`, `dt` (s) the time since it, for the velocity limit;
/// nullopt: none (the first command). `revolute`: targets are angles, wrapped.
JointCommand actuatorCommand(const ActuatorSpec& a, const JointDrive& current, bool revolute,
                             double t, double q, std::optional<double> previousTarget, double dt);

/// Empty if the actuator is valid for `model`, otherwise the problem (names the field).
std::string checkActuator(const ActuatorSpec& a, const Model& model);

}  // namespace robophi::build
