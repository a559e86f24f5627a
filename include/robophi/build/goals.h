#pragma once
/// \file
/// What a robot is asked to reach or avoid, built into a model definition
/// (MODEL §5, docs/robotics.md): a goal (a virtual copy of the robot at the goal
/// pose, tied to it by attractor LS), a path constraint (line or arc), an obstacle
/// grown by a security distance, and LS that pull finger tips together. Each
/// builder appends particles and connectors to a Model and its initial State; a
/// goal also returns the task spec (build/tasks.h) the application checks between
/// steps. A bad argument throws std::invalid_argument naming it, before anything
/// is added.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/tasks.h"
#include "robophi/model.h"
#include "robophi/state.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// Rest length (m) of an attractor LS: the law needs l0 > 0, and this is zero in effect.
inline constexpr double kAttractorRestLength = 1.0e-9;
/// Radius (m) of a virtual particle, small so that it hardly ever touches anything.
inline constexpr double kVirtualRadius = 1.0e-4;

/// Where `particles` go when moved as one rigid body about their centroid c: each
/// position x becomes c + R (x − c) + translation, R the rotation by `angle` (rad)
/// about `axis` (any length; a zero axis means no rotation).
std::vector<Vec3> movedPose(const std::vector<Vec3>& position,
                            const std::vector<ParticleIndex>& particles, const Vec3& translation,
                            const Vec3& axis = {}, double angle = 0.0);

/// A goal (MODEL §5.1): the robot's particles attracted by LS to fixed virtual
/// copies at the goal pose.
struct AttractorGoalSpec {
  /// Names the goal (GoalSpec::name) and the "virtual" object holding the copies.
  std::string name = "goal";
  /// The attracted robot particles, and where each must go (m), one per particle.
  std::vector<ParticleIndex> particles;
  std::vector<Vec3> goalPositions;
  /// Attractor LS stiffness (N/m), > 0, and damping (N·s/m), >= 0.
  double stiffness = 1.0;
  double damping = 0.0;
  /// Speed (m/s) of a moving virtual robot, >= 0: the copies start on the robot
  /// and travel in straight lines so that the farthest arrives at this speed, all
  /// at the same time. 0: the copies stand at the goal from the start.
  double speed = 0.0;
  /// Reached when every particle is within `tolerance` (m) of its copy and moves
  /// slower than `speedTolerance` (m/s); both > 0.
  double tolerance = 0.01;
  double speedTolerance = 0.05;
  /// End the run when the goal is reached.
  bool stopWhenReached = false;
};

/// Adds the goal's virtual object (fixed particles, moving kinematically when
/// `speed` > 0) and one attractor LS per particle. Returns the goal's task spec.
GoalSpec addGoal(Model& model, State& state, const AttractorGoalSpec& spec);

/// A point fixed to a link of a rigid robot (a tree's body or named frame, e.g.
/// "iiwa.iiwa_link_7"), to be named in a goal or path like a particle.
struct LinkPointSpec {
  /// The body or frame name (Multibody::bodies[].name or frames[].name).
  std::string link;
  /// The point in the link's frame (m).
  Vec3 p_LP{};
};

/// Adds a particle carried by the link at the point and returns its index: the one
/// particle of a new "virtual" object `name` (it touches nothing and has no weight),
/// which the tree's step moves with the link and whose loads (an attractor's pull)
/// it gathers into the link's wrench (docs/model.md §7), so that a goal pulls the
/// link itself. Throws std::invalid_argument when no rigid tree has that link or
/// the point is not finite.
ParticleIndex addLinkPoint(Model& model, State& state, const LinkPointSpec& spec,
                           const std::string& name);

/// A line path (MODEL §5.1): a TS at 180° centred on the particle, its ends two
/// fixed virtual particles at `from` and `to`, keeps the particle on the segment.
struct LinePathSpec {
  /// Names the "virtual" object holding the two ends.
  std::string name = "path";
  /// The guided particle; it must start on the segment.
  ParticleIndex particle = 0;
  /// The segment's ends (m), different.
  Vec3 from, to;
  /// TS stiffness (N·m/rad), > 0, and damping (N·m·s/rad), >= 0.
  double stiffness = 1.0;
  double damping = 0.0;
};
void addLinePath(Model& model, State& state, const LinePathSpec& spec);

/// An arc path (MODEL §5.1, the paper's mechanism): a TS centred on the
/// particle, its ends two fixed virtual points A and B, at rest at the angle
/// A-particle-B it starts with. By the inscribed angle theorem the points that
/// see the chord AB under that angle form the arc of circle through A, B and
/// the particle's start: the TS keeps the particle on it. Optionally a second TS
/// at 90° (centre, particle, heading particle) keeps the robot's heading tangent.
struct ArcPathSpec {
  /// Names the "virtual" object holding the ends (and the centre, with a heading).
  std::string name = "path";
  /// The guided particle; it must not start on the line through the ends.
  ParticleIndex particle = 0;
  /// The ends A and B (m), different: two points of the circle, off the stretch
  /// of arc the particle travels (it stays on the side of AB where it starts).
  Vec3 from, to;
  /// TS stiffness (N·m/rad), > 0, and damping (N·m·s/rad), >= 0.
  double stiffness = 1.0;
  double damping = 0.0;
  /// The robot particle that points along the heading; none: no heading TS.
  std::optional<ParticleIndex> heading;
  /// Heading TS stiffness (N·m/rad), > 0; default `stiffness`.
  std::optional<double> headingStiffness;
};
/// The circle's centre (m) through three points (not on one line).
Vec3 circleCenter(const Vec3& a, const Vec3& b, const Vec3& c);
void addArcPath(Model& model, State& state, const ArcPathSpec& spec);

/// The shape of an obstacle to avoid.
enum class ObstacleShape : std::uint8_t { kSphere, kBox };

/// An obstacle the robot must keep away from (MODEL §5.2): an environment sphere
/// or axis-aligned box, grown by the security distance on every side, so that
/// contact with the grown obstacle keeps the robot that far from the real one.
struct ObstacleSpec {
  ObstacleShape shape = ObstacleShape::kSphere;
  /// Centre (m).
  Vec3 center;
  /// Sphere: radius (m), > 0.
  double radius = 0.5;
  /// Box: full sides (m), each > 0.
  Vec3 size{1.0, 1.0, 1.0};
  /// Security distance (m), >= 0.
  double securityDistance = 0.0;
};
void addObstacle(Model& model, const ObstacleSpec& spec);

/// MODEL §5.3: an attractor LS between every two finger tips, stiffness (N/m)
/// > 0 and damping (N·s/m) >= 0, pulling the hand closed on the object.
void addTipAttractors(Model& model, const std::vector<ParticleIndex>& tips, double stiffness,
                      double damping);

}  // namespace robophi::build
