#pragma once
/// \file
/// What a model asks its robots to do between steps (docs/robotics.md): joint
/// limits, goals to reach, local-minimum escape, grasp checks. Plain data: the
/// goal builders (build/goals.h) and the scene's "robotics" section fill it, and
/// the application's robotics::makeSceneTasks (robophi/robotics/tasks.h) turns it
/// into the runner's between-steps hook. Nothing here runs in the step.

#include <cstdint>
#include <string>
#include <vector>

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
  /// Radius (m) of each virtual obstacle; it is placed this far plus the
  /// particle's radius behind the stopped particle, on the side of the goal.
  double obstacleRadius = 0.1;
  /// Most virtual obstacles added.
  int maxObstacles = 10;
};

/// Grasp check (MODEL §5.3): the object must come to rest in the hand and stay
/// within `tolerance` of where it settled, also after a velocity disturbance.
struct GraspSpec {
  /// Object index (Model::objects) of the grasped object.
  std::int32_t object = -1;
  /// Time (s) allowed to settle; the object's rest position is taken then.
  double settleTime = 1.0;
  /// Largest allowed displacement of the object's centre of mass (m).
  double tolerance = 0.01;
  /// Velocity change (m/s) given to every particle of the object at `disturbanceTime`.
  Vec3 disturbance{0.0, 0.0, 0.0};
  double disturbanceTime = -1.0;
};

/// Every robotics task of a scene.
struct SceneTasks {
  std::vector<JointLimitSpec> limits;
  std::vector<GoalSpec> goals;
  std::vector<EscapeSpec> escapes;
  std::vector<GraspSpec> grasps;
  bool empty() const {
    return limits.empty() && goals.empty() && escapes.empty() && grasps.empty();
  }
};

}  // namespace robophi::build
