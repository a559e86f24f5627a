#pragma once
/// \file
/// robotics::Controller (docs/robots.md "Controlling joints"): per joint a
/// position, velocity or effort actuator with gains, limits and a target that
/// changes in time; mimic joints; moving bases; a sequence of phases started at
/// times, after delays or by conditions. A Task (robotics/task.h): it acts
/// between steps through World's edits (servo targets and gains, MODEL §1.5;
/// joint drives, MODEL §1.6; fixed particles' positions and velocities, MODEL
/// §2.3), and saves and restores its state bit-exactly for a checkpoint.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/control.h"
#include "robophi/world.h"
#include "robotics/task.h"

namespace robophi::robotics {

using build::ActuatorSpec;
using build::BaseMotionSpec;
using build::ConditionSpec;
using build::ControlSpec;
using build::JointMode;
using build::MimicSpec;
using build::PhaseSpec;
using build::Trajectory;

/// Applies a ControlSpec between steps; also driven by hand through its setters
/// (callable between steps; they take effect at the next apply or step).
class Controller : public Task {
 public:
  /// Throws std::invalid_argument when a spec does not fit `model` (naming it).
  explicit Controller(ControlSpec spec, const Model& model);

  /// The actuator of its joint, replacing the joint's previous one; its
  /// trajectory's time starts at the next apply.
  void setActuator(const ActuatorSpec& actuator);
  /// Changes the mode of a joint's actuator (gains and target kept); a joint
  /// without an actuator gets one, with zero gains.
  void setMode(std::size_t joint, JointMode mode);
  /// A constant target (rad or m, rad/s or m/s, N·m or N, by mode).
  void setTarget(std::size_t joint, double value);
  /// A target trajectory, its time counted from the next apply.
  void setTrajectory(std::size_t joint, const Trajectory& trajectory);
  /// Position gains kp (N·m/rad or N/m) and kd (N·m·s/rad or N·s/m); velocity gain kv.
  void setGains(std::size_t joint, double kp, double kd, double kv = 0.0);
  void addMimic(const MimicSpec& mimic);
  /// Starts a base motion now (at the next apply), replacing one of the same name.
  void setBaseMotion(const BaseMotionSpec& base);

  /// Brings the world's servos, drives and bases to the commands at the world's
  /// time, starting phases whose condition holds. Call it before the first step
  /// (the scene runner's first call comes after it); step() calls it.
  void apply(World& world, std::vector<std::string>* events = nullptr);

  /// apply() at the start of a run.
  void start(World& world, std::vector<std::string>& events) override { apply(world, &events); }
  bool step(World& world, std::vector<std::string>& events) override;
  nlohmann::json save() const override;
  void restore(const nlohmann::json& saved) override;
  /// {"control": {"phases": [{"name", "started_s", "by"}...]}}.
  nlohmann::json outcomes(const World& world) const override;

  /// When each phase started (s); < 0: not yet.
  const std::vector<double>& phaseStarts() const { return phaseStarts_; }
  /// The actuator of `joint`, or nullptr.
  const ActuatorSpec* actuator(std::size_t joint) const;
  /// The position target q* (rad or m) the servo of `joint` was last given.
  double servoTarget(std::size_t joint) const;

 private:
  struct Channel {
    ActuatorSpec spec;
    /// When its trajectory started (s); < 0: at the next apply.
    double start = -1.0;
    /// The last rate-limited target (position mode) and when (s); unset at first.
    std::optional<double> command;
    double commandTime = 0.0;
    double servoTarget = 0.0;
  };
  struct Base {
    BaseMotionSpec spec;
    double start = -1.0;
    std::vector<Vec3> origin;
  };
  Channel& channel(std::size_t joint);
  void startPhase(std::size_t phase, World& world, double t, const std::string& reason,
                  std::vector<std::string>* events);
  /// The reason phase `phase`'s condition holds at the world's state, or nullopt.
  std::optional<std::string> conditionHolds(const ConditionSpec& c, const World& world,
                                            double t) const;
  void applyChannel(Channel& c, World& world, double t);
  void applyBase(Base& b, World& world, double t);

  ControlSpec spec_;
  std::size_t jointCount_ = 0;
  std::vector<Channel> channels_;
  std::vector<Base> bases_;
  std::vector<double> phaseStarts_;
  std::vector<std::string> phaseReasons_;
  /// The next phase to start.
  std::size_t nextPhase_ = 0;
};

}  // namespace robophi::robotics
