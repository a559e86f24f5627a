#pragma once
/// \file
/// Robotics tasks that run between steps (docs/robotics.md, MODEL §5): goal
/// monitoring, local-minimum escape with virtual obstacles, grasp checks, joint
/// limits. They observe the World and change it only through its public API.

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/tasks.h"
#include "robophi/contact.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"
#include "robotics/joint_control.h"
#include "robotics/task.h"

namespace robophi::robotics {

// The task specs are plain data of the build layer (robophi/build/tasks.h).
using build::EscapeSpec;
using build::GoalSpec;
using build::GraspSpec;
using build::SceneTasks;

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
  /// Its state for a checkpoint, and back (robotics/task.h).
  nlohmann::json save() const;
  void restore(const nlohmann::json& saved);

 private:
  EscapeSpec spec_;
  /// Time (s) since when the robot is stopped away from the goal; < 0: moving.
  double stoppedSince_ = -1.0;
  std::vector<SphereObstacle> added_;
  /// Where the attracted particles started (m), taken at the first update.
  std::vector<Vec3> start_;
  /// The side (unit) the virtual obstacles push towards, chosen at the first one.
  std::optional<Vec3> side_;
  /// How deep a new virtual obstacle overlaps the stuck particle, as a fraction of its radius.
  static constexpr double kOverlap = 0.5;
};

/// MODEL §5.3: watches a grasped object: rest position after settling, drift
/// after it, and a velocity disturbance at a set time.
class GraspCheck {
 public:
  explicit GraspCheck(GraspSpec spec) : spec_(spec) {}
  /// Call after each step; returns a description of what happened, if anything.
  std::optional<std::string> update(World& world);
  bool settled() const { return settled_; }
  /// Largest distance (m) of the object's centre of mass from its rest position since it settled.
  double largestDrift() const { return largestDrift_; }
  /// Stable so far: settled and never beyond the tolerance.
  bool stable() const { return settled_ && largestDrift_ <= spec_.tolerance; }
  /// A one-line verdict with the figures.
  std::string verdict() const;
  /// The verdict as data (summary.json "outcomes"."grasps").
  nlohmann::json outcome() const;
  /// Its state for a checkpoint, and back (robotics/task.h).
  nlohmann::json save() const;
  void restore(const nlohmann::json& saved);

 private:
  GraspSpec spec_;
  bool settled_ = false, disturbed_ = false;
  double settledAt_ = -1.0;
  Vec3 rest_;
  double largestDrift_ = 0.0;
};

/// The centre of mass (m) of object `object`.
Vec3 objectCenterOfMass(const World& world, std::int32_t object);

/// The scene's robotics tasks as one task between steps (robotics/task.h; pass
/// it first in RunOptions::tasks): it adds what happened to `events`, returns
/// false when a goal that stops the run is reached, reports its goals' and
/// grasps' outcomes as data (Task::outcomes: {"goals": [{"name", "reached",
/// "time_s", "final_distance_m", "tolerance_m"}], "grasps": [...]}) and saves and
/// restores its state for a checkpoint. Empty when the scene has none.
StepTask makeSceneTasks(const Scene& scene);

}  // namespace robophi::robotics
