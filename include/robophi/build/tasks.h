#pragma once
/// \file
/// What a model asks its robots to do between steps (docs/robotics.md): joint
/// limits, goals to reach, local-minimum escape, grasp checks. Plain data: the
/// goal builders (build/goals.h) and the scene's "robotics" section fill it, and
/// the application's robotics::makeSceneTasks (robophi/robotics/tasks.h) turns it
/// into the runner's between-steps hook. Nothing here runs in the step.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/build/control.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// A joint limit (MODEL §1 joints): outside [min, max] the joint becomes a stiff
/// servo to the violated bound; back inside, its own settings return.
struct JointLimitSpec {
  /// Index into Model::joints.
  std::size_t joint = 0;
  /// Bounds (rad for a revolute joint, in [0, 2π); m for a prismatic one).
  double min = 0.0, max = 0.0;
  /// Stiffness (N·m/rad or N/m) and damping of the limit servo.
  double stiffness = 0.0, damping = 0.0;
};

/// A goal (MODEL §5.1): robot particles attracted by LS to fixed virtual copies.
struct GoalSpec {
  std::string name;
  /// The attracted particles and their virtual copies at the goal pose.
  std::vector<ParticleIndex> particles, targets;
  /// Reached when every particle is within `tolerance` (m) of its target and
  /// moves slower than `speedTolerance` (m/s).
  double tolerance = 0.01, speedTolerance = 0.05;
  /// End the run when the goal is reached.
  bool stopWhenReached = false;
  /// A moving virtual robot: its particles start on the robot's and travel in
  /// straight lines at constant velocity (fixed particles move kinematically)
  /// to the goal pose, all arriving after `travelTime` (s), where they stop.
  /// 0: the virtual robot stands at the goal from the start.
  double travelTime = 0.0;
  /// The goal pose (m), one position per target.
  std::vector<Vec3> goalPositions;
};

/// Local-minimum escape (MODEL §5.2) for a goal: when the attracted particles are
/// slow (< speedThreshold) and away from their targets for `window` seconds, a
/// virtual sphere obstacle is added at the local minimum, one after another.
struct EscapeSpec {
  /// Index into SceneTasks::goals.
  std::size_t goal = 0;
  /// Mean speed (m/s) below which the robot counts as stopped.
  double speedThreshold = 0.02;
  /// Time (s) it must stay stopped away from the goal.
  double window = 0.3;
  /// Radius (m) of each virtual obstacle. 0: the radius of the robot where it
  /// is blocked (its blocking particles', or its ball's).
  double obstacleRadius = 0.0;
  /// Most virtual obstacles added.
  int maxObstacles = 200;
  /// Not stuck, but settling: within this distance (m) of its target the robot
  /// is left alone (an arm sagging under gravity near its goal). 0: 5 × the
  /// goal's tolerance.
  double settleDistance = 0.0;
  /// Most work (J) one virtual obstacle may inject (its place is backed off
  /// until it fits). 0: 1 % of the scene's energy scale (the largest kinetic
  /// and elastic energy so far, as the run's energy account has it).
  double maxWork = 0.0;
  /// Most work (J) all the virtual obstacles may inject; once spent, no more
  /// come (the goal is reported not reached). 0: 10 % of the energy scale.
  double workBudget = 0.0;
  /// Once a local minimum is found, a further obstacle every `pushInterval` (s)
  /// while the robot is still held there (0: three per `window`), each from the
  /// same side: small pushes one after another, until it is free (nearer its
  /// goal by a tenth of the distance it was stuck at, or touching nothing).
  double pushInterval = 0.0;
};

/// Grasp check (MODEL §5.3, the paper's criterion): the hand closes on a free
/// object by its joints; the object must come to rest in the hand (its centre of
/// mass and its rotation about it slower than the thresholds for `settleHold`
/// seconds: settled by velocity, not by the clock), and stay within `tolerance`
/// of where it settled, also through a velocity disturbance. The hand's net
/// force and torque on the object are measured from the contact forces.
struct GraspSpec {
  /// Object indices (Model::objects) of the grasped object and of the hand (-1:
  /// every other object counts as the hand).
  std::int32_t object = -1;
  std::int32_t hand = -1;
  /// Joints (Model::joints) that close the hand: each target moves by
  /// `closeAngle` (rad, > 0) towards the object, linearly over `closeTime` (s).
  std::vector<std::size_t> closeJoints;
  double closeAngle = 0.0;
  double closeTime = 0.0;
  /// Settled: centre-of-mass speed below `settleSpeed` (m/s) and angular speed
  /// about the centre of mass below `settleAngularSpeed` (rad/s), both for
  /// `settleHold` (s), after the closing.
  double settleSpeed = 1e-3;
  double settleAngularSpeed = 1e-2;
  double settleHold = 0.5;
  /// Largest allowed displacement of the object's centre of mass (m) from where it settled.
  double tolerance = 0.01;
  /// Velocity change (m/s) given to every particle of the object at
  /// `disturbanceTime` (s), or as soon as it has settled if that is later; < 0: none.
  Vec3 disturbance{0.0, 0.0, 0.0};
  double disturbanceTime = -1.0;
};

/// What became of a goal (MODEL §5.1, §5.2): the machine-readable outcome the
/// run's summary reports and the exit status follows.
struct GoalOutcome {
  std::string name;
  bool reached = false;
  /// When it was reached (s); < 0: not (yet).
  double reachedAt = -1.0;
  /// Largest distance (m) of an attracted particle from its target, at the last step.
  double distance = 0.0;
  /// Virtual obstacles the escape added, and the work (J) they injected in all.
  int virtualObstacles = 0;
  double escapeWork = 0.0;
};

/// The grasp verdict (MODEL §5.3): figures at the last step.
struct GraspOutcome {
  std::string object;
  /// Settled (by velocity) and when (s; < 0: never).
  bool settled = false;
  double settledAt = -1.0;
  /// The disturbance was given, and the object settled again after it (when, s).
  bool disturbed = false;
  bool resettled = false;
  double resettledAt = -1.0;
  /// Largest distance (m) of the centre of mass from its rest position since it settled.
  double largestDrift = 0.0;
  double tolerance = 0.0;
  /// Settled, never beyond the tolerance, and (if disturbed) settled again.
  bool stable = false;
  /// The hand's net force (N) and torque about the object's centre of mass (N·m)
  /// on the object, from the contact forces, and the grip: the sum of the
  /// contacts' normal forces (N).
  Vec3 netForce{};
  Vec3 netTorque{};
  double gripForce = 0.0;
  /// Hand–object contacts, and those of them with the hand's fixed particles (the palm).
  int contacts = 0;
  int fixedContacts = 0;
  /// The object's centre-of-mass speed (m/s) and angular speed about it (rad/s).
  double speed = 0.0;
  double angularSpeed = 0.0;
};

/// Every task's outcome, kept current after each step by the application's
/// robotics tasks (robotics::makeSceneTaskHook).
struct TaskOutcomes {
  std::vector<GoalOutcome> goals;
  std::vector<GraspOutcome> grasps;
  /// False when a goal was not reached (the run exits with its own status).
  bool goalsReached() const {
    for (const GoalOutcome& g : goals)
      if (!g.reached) return false;
    return true;
  }
  bool graspsStable() const {
    for (const GraspOutcome& g : grasps)
      if (!g.stable) return false;
    return true;
  }
};

/// Every robotics task of a scene.
struct SceneTasks {
  std::vector<JointLimitSpec> limits;
  std::vector<GoalSpec> goals;
  std::vector<EscapeSpec> escapes;
  std::vector<GraspSpec> grasps;
  /// Actuators, mimic joints, moving bases and sequences (build/control.h).
  ControlSpec control;
  bool empty() const {
    return limits.empty() && goals.empty() && escapes.empty() && grasps.empty() && control.empty();
  }
};

}  // namespace robophi::build
