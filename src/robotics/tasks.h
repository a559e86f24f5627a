#pragma once
/// \file
/// Robotics tasks that run between steps (docs/robotics.md, MODEL §5): goal
/// monitoring, local-minimum escape with virtual obstacles, grasp checks, joint
/// limits. They observe the World and change it only through its public API.

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/tasks.h"
#include "robophi/contact.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "robotics/controller.h"
#include "robotics/joint_control.h"
#include "robotics/task.h"

namespace robophi::robotics {

// The task specs are plain data of the build layer (robophi/build/tasks.h).
using build::EscapeSpec;
using build::GoalOutcome;
using build::GoalSpec;
using build::GraspOutcome;
using build::GraspSpec;
using build::SceneTasks;
using build::TaskOutcomes;

/// Where the robot stands with respect to a goal.
struct GoalStatus {
  /// Largest distance (m) of an attracted particle from its virtual copy.
  double worstDistance = 0.0;
  /// Mean speed (m/s) of the attracted particles.
  double meanSpeed = 0.0;
  bool reached = false;
};
GoalStatus goalStatus(const World& world, const GoalSpec& goal);

/// A moving virtual robot (GoalSpec::travelTime > 0) that has come to the end
/// of its travel is put exactly at the goal pose and stopped (travelTime
/// becomes 0); returns a description then.
std::optional<std::string> arriveVirtualRobot(World& world, GoalSpec& goal);

/// MODEL §5.2: detects a local minimum (slow, away from the goal, for a while)
/// and adds virtual sphere obstacles there, one after another, until it escapes.
class LocalMinimumEscape {
 public:
  explicit LocalMinimumEscape(EscapeSpec spec) : spec_(spec) {}
  /// Call after each step with the goal it watches (SceneTasks::goals[spec.goal],
  /// as the run holds it: a moving virtual robot changes); returns a
  /// description when it added an obstacle.
  std::optional<std::string> update(World& world, const GoalSpec& goal);
  /// Index of the goal it watches (SceneTasks::goals).
  std::size_t goal() const { return spec_.goal; }
  /// The virtual obstacles added so far, in order.
  const std::vector<SphereObstacle>& added() const { return added_; }
  /// The work (J) the virtual obstacles injected, as booked by the World.
  double work() const { return work_; }
  /// Its state for a checkpoint, and back (robotics/task.h).
  nlohmann::json save() const;
  void restore(const nlohmann::json& saved);

 private:
  EscapeSpec spec_;
  /// Time (s) since when the robot is stopped away from the goal; < 0: moving.
  double stoppedSince_ = -1.0;
  /// Pushing it out of a local minimum: since when, how far from the goal it
  /// was stuck (m), when the last obstacle came, and how many this minimum took.
  bool pushing_ = false;
  double stuckDistance_ = 0.0, lastPush_ = 0.0, pushStart_ = 0.0;
  /// While pushing: since when (s) it touches nothing outside itself; < 0: it touches.
  double untouchedSince_ = -1.0;
  int pushes_ = 0;
  double pushWork_ = 0.0;
  std::vector<SphereObstacle> added_;
  double work_ = 0.0;
  /// The side (unit) the virtual obstacles push towards, chosen at the first one.
  std::optional<Vec3> side_;
  /// The largest kinetic and elastic energy seen (J): the scale of the budgets.
  double energyScale_ = 0.0;
  /// The virtual obstacles' material (frictionless), made at the first; -1 before.
  std::int32_t material_ = -1;
};

/// MODEL §5.3, the paper's criterion: closes the hand by its joints, detects by
/// velocity when the free object has come to rest in it, measures the hand's
/// net force and torque on it, gives the disturbance, and follows its drift.
class GraspCheck {
 public:
  /// `model` names the object in the outcome.
  GraspCheck(GraspSpec spec, const Model& model);
  /// Call after each step; returns a description of what happened, if anything.
  std::optional<std::string> update(World& world);
  bool settled() const { return outcome_.settled; }
  /// Largest distance (m) of the object's centre of mass from its rest position since it settled.
  double largestDrift() const { return outcome_.largestDrift; }
  /// Stable so far: settled, never beyond the tolerance, settled again after a disturbance.
  bool stable() const { return outcome_.stable; }
  /// The figures at the last update.
  const GraspOutcome& outcome() const { return outcome_; }
  /// A one-line verdict with the figures.
  std::string verdict() const;
  /// Its state for a checkpoint, and back (robotics/task.h).
  nlohmann::json save() const;
  void restore(const nlohmann::json& saved);

 private:
  GraspSpec spec_;
  GraspOutcome outcome_;
  /// The closing joints' start values (rad) and directions (±1), taken at the first update.
  std::vector<double> start_, direction_;
  /// Since when (s) the object is slow; < 0: moving.
  double slowSince_ = -1.0;
  Vec3 rest_;
};

/// The centre of mass (m) of object `object`.
Vec3 objectCenterOfMass(const World& world, std::int32_t object);

/// How an object moves about its centre of mass: the centre's velocity (m/s)
/// and the angular velocity (rad/s) of the rigid motion that best fits its
/// particles' velocities (I⁻¹ L about the centre of mass).
struct ObjectMotion {
  Vec3 center, velocity, angularVelocity;
};
ObjectMotion objectMotion(const World& world, std::int32_t object);
/// The same for a state of `model` (a run's final state, say).
ObjectMotion objectMotion(const Model& model, const State& state, std::int32_t object);

/// The scene's robotics tasks as one task between steps (robotics/task.h; pass
/// it first in RunOptions::tasks): it adds what happened to `events`, returns
/// false when a goal that stops the run is reached, reports its goals' and
/// grasps' outcomes as data (Task::outcomes, summary.json "outcomes":
/// docs/output-format.md) and saves and restores its state for a checkpoint.
/// `outcomes` holds the same figures as structs, current after each step.
struct SceneTaskHook {
  /// Empty when the scene has no robotics tasks.
  StepTask task;
  /// Never null; empty lists when the scene has no goals or grasps.
  std::shared_ptr<const TaskOutcomes> outcomes;
};
SceneTaskHook makeSceneTaskHook(const Scene& scene);

/// makeSceneTaskHook(scene).task, for callers that need no outcome structs.
StepTask makeSceneTasks(const Scene& scene);

}  // namespace robophi::robotics
