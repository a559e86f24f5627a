#pragma once
/// \file
/// The URDF importer (docs/robots.md "Importing a URDF"): a robot description
/// → particle bodies, one placed object per link, joined by the paper's
/// connectors (MODEL §1.4): a revolute or continuous joint is an axis (centre c
/// and axis point d, particles of the child) that the parent holds by LS, and a
/// JS a-c-b-d; a prismatic joint is two TS at 180° (origin and end on the
/// parent, two sliders on the child), a drive LS and a stiff JS that locks the
/// roll; a fixed joint ties the child to its parent by LS. Links are filled by
/// makeRigidBody (build/rigid_body.h) so that their particles carry the URDF's
/// mass, centre of mass and inertia.
///
///     build::UrdfSpec spec{.path = "robots/kuka_iiwa/model.urdf"};
///     build::UrdfRobot robot = build::makeUrdfRobot(spec);
///     build::ModelBuilder builder;
///     build::placeUrdfRobot(builder, robot);

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "robophi/build/model_builder.h"
#include "robophi/build/rigid_body.h"
#include "robophi/build/urdf_error.h"
#include "robophi/build/urdf_visuals.h"

namespace robophi::build {

/// The most links with particles (bodies) a URDF robot may have
/// (docs/scene-format.md#limits), checked before any link is filled: the model
/// keeps lists that grow as their square (without self-collision every pair of
/// links that never touch; per joint, the bodies it carries), 12.5 million
/// entries for a chain of 5 000. The robot's particles are held to the scene's
/// budget (kMaxParticlesPerObject) as its links are filled, and before that by
/// their count × particlesPerLink.
inline constexpr int kMaxUrdfBodies = 5'000;

/// What to import and how.
struct UrdfSpec {
  /// The URDF file (a .xacro file is refused: run xacro first).
  std::string path{};
  /// Folders searched for package://NAME/... meshes (NAME a folder directly
  /// under one of them, or the folder itself called NAME), before ROS_PACKAGE_PATH.
  std::vector<std::string> packagePaths{};
  /// Prefix of the object and joint names ("<name>.<link>", "<name>.<joint>"); empty: the
  /// URDF's robot name.
  std::string name{};
  /// Where the root link's frame is in the world.
  Frame placement{};
  /// The root link's particles fixed (a mounted arm); false: the robot is free.
  bool fixedBase = true;
  /// Lattice spacing of every link (m), >= 0; 0: about particlesPerLink particles a link.
  double particleSize = 0.0;
  /// Particles a link when particleSize is 0, >= 1.
  int particlesPerLink = 30;
  /// Natural frequency of each link's fastest mode (rad/s), > 0 (objects.h's stiffness rule);
  /// the joint connectors are as stiff as the links they join.
  double naturalFrequency = kDefaultNaturalFrequency;
  /// Joint positions q (rad, m) the robot is built at, by URDF joint name; the others at 0.
  std::map<std::string, double> initialPositions{};
  /// Links of the robot touch each other (never a joint's parent and child); default: not.
  bool selfCollision = false;
  /// Every moving joint held where it is built by its servo at the hold gains
  /// (UrdfJoint::holdStiffness, holdDamping) with gravity compensation
  /// (Joint::compensateGravity): a bare `robophi run`. false: passive joints (servo
  /// off, the URDF's damping), for the controllers to drive.
  bool holdJoints = false;
  /// The frequency (rad/s, >= 0; 0: 0.3 naturalFrequency) of the links' shape matching,
  /// of the body links that hold them together and of the joints' hold gains (MODEL
  /// §1.7): κ = ω² I for the pair's reduced inertia about the axis (kg·m²; mass, kg, for
  /// a prismatic joint), critically damped. On the iiwa, 0.36 naturalFrequency ran
  /// stable and 0.44 did not (explicit steps at the lattice's bound).
  double servoFrequency = 0.0;
  /// Round wheels (docs/contact.md "Round wheels"): a link whose one <collision> is a
  /// cylinder coaxial with its revolute or continuous joint meets the environment as
  /// that cylinder (its true radius), not as its lattice's spheres; false: as a lattice.
  bool roundWheels = true;
};

/// A URDF joint's kind.
enum class UrdfJointType { kRevolute, kContinuous, kPrismatic, kFixed };

/// One URDF link as imported.
struct UrdfLink {
  std::string name{};
  /// The URDF's line of its <link>.
  int line = 0;
  /// Index into UrdfRobot::objects of its particles, -1 for a frame (a link without
  /// mass on a fixed joint: it has no particles, it moves with `attachedTo`).
  int object = -1;
  /// Index into UrdfRobot::objects of its carriers (kind "virtual": inertia the geometry
  /// cannot hold, carried by particles outside it that touch nothing), -1 for none.
  int carrierObject = -1;
  /// The link its frame moves with (index into UrdfRobot::links): itself when it has particles.
  int attachedTo = -1;
  /// Its frame in the world at the build pose.
  Frame frame{};
  /// The URDF's <inertial>: mass properties in the link frame (declared), and in the world at
  /// the build pose; mass 0 for a link without one.
  MassProperties declared{};
  MassProperties declaredWorld{};
  /// The particles' mass properties, link frame (achieved).
  MassProperties achieved{};
  /// The link has notional particles: a fixed base without mass of its own (e.g. the iiwa's
  /// link_0, mass 0), given `notionalMass`; its mass properties are not the URDF's.
  bool notional = false;
  /// A round wheel (UrdfSpec::roundWheels): its object's particles meet the environment
  /// as its cylinder (robophi::RimRing::isCylinder).
  bool roundWheel = false;
  /// What makeRigidBody had to do (carriers added, no collision geometry...).
  std::vector<std::string> notes{};
};

/// One URDF joint as imported (plain data for the controllers: limits, dynamics, mimic).
struct UrdfJoint {
  std::string name{};
  int line = 0;
  UrdfJointType type = UrdfJointType::kFixed;
  /// Unit axis in the joint frame (URDF <axis>), and in the world at the build pose.
  Vec3 axis{1, 0, 0};
  Vec3 worldAxis{1, 0, 0};
  /// Indices into UrdfRobot::links.
  int parent = -1, child = -1;
  /// <limit>: position (rad or m; continuous: none), velocity (rad/s, m/s), effort (N·m, N).
  bool hasPositionLimits = false;
  double lower = 0, upper = 0, velocity = 0, effort = 0;
  /// <dynamics>: damping (N·m·s/rad, N·s/m, applied as the joint's connector damping) and
  /// friction (N·m, N: recorded for the controllers).
  double damping = 0, friction = 0;
  /// <mimic>: q = multiplier q_joint + offset.
  bool hasMimic = false;
  std::string mimicJoint{};
  double multiplier = 1.0, offset = 0.0;
  /// The position q (rad, m) it is built at.
  double initialPosition = 0.0;
  /// A wheel: a continuous joint whose child has a <collision> round about its line
  /// (build::roundAbout). A robot on two or more stands free on them.
  bool wheel = false;
  /// The model's joint "<object>.<name>" (Model::joints) for a moving joint; empty for fixed.
  std::string modelJoint{};
  /// A moving joint's hold gains (UrdfSpec::servoFrequency): the servo stiffness (N·m/rad
  /// or N/m) and damping (N·m·s/rad or N·s/m) that its links' inertia allows at that
  /// frequency; a position controller's gains are best kept at or below them.
  double holdStiffness = 0.0, holdDamping = 0.0;
};

/// An LS, TS or JS between particles of two placed objects: (object, local index) pairs.
struct UrdfParticle {
  int object = 0;
  int local = 0;
};
struct UrdfLinearSpring {
  UrdfParticle a, b;
  double restLength = 0, stiffness = 0, damping = 0;
};
struct UrdfTorsionSpring {
  UrdfParticle a, c, b;
  double restAngle = 0, stiffness = 0, damping = 0;
};
struct UrdfJointSpring {
  UrdfParticle a, c, b, d;
  double restAngle = 0, stiffness = 0, damping = 0;
};
/// A named joint over those connectors: revolute → jointSprings[connector]; prismatic →
/// torsionSprings[connector] and the drive linearSprings[driveSpring].
struct UrdfModelJoint {
  std::string name{};  // "<robot>.<joint>"
  JointKind kind = JointKind::kRevolute;
  int connector = -1;
  int driveSpring = -1;
  double zero = 0.0;
  /// Index into UrdfRobot::bodyLinks of the link that holds its two bodies (Joint::bodyLink).
  int bodyLink = -1;
  /// Its servo (Joint::servoStiffness, servoDamping; servoTarget a raw value).
  double servoStiffness = 0.0, servoDamping = 0.0, servoTarget = 0.0;
  /// Its drive (Joint::drive): the URDF's <dynamics> damping and friction and its
  /// <limit> effort and velocity (where > 0); no motor.
  JointDrive drive{};
};

/// A body link (MODEL §1.7) between two links' bodies: indices into UrdfRobot::links
/// (each body is a link's object and its carriers), the joint point and axis in the
/// world as built, and the gains (BodyLink's stiffness, damping, angularStiffness,
/// angularDamping).
struct UrdfBodyLink {
  BodyLinkKind kind = BodyLinkKind::kRevolute;
  int child = -1, parent = -1;
  Vec3 point{}, axis{0, 0, 1};
  BodyLink gains{};
};

/// The imported robot: what ModelBuilder places (placeUrdfRobot) and what it came from.
struct UrdfRobot {
  std::string name{};  // <robot name>
  std::string file{};
  /// One object per link with particles, named "<robot>.<link>", kind "link", rigid; then
  /// the links' carriers, "<robot>.<link>.carriers", kind "virtual".
  std::vector<ObjectPlacement> objects{};
  std::vector<UrdfLink> links{};
  std::vector<UrdfJoint> joints{};
  /// Connectors between the objects (the joints' and the fixed ties).
  std::vector<UrdfLinearSpring> linearSprings{};
  std::vector<UrdfTorsionSpring> torsionSprings{};
  std::vector<UrdfJointSpring> jointSprings{};
  std::vector<UrdfModelJoint> modelJoints{};
  /// Every link with particles is a rigid body (MODEL §1.7) shape-matched at
  /// `bodyFrequency` (rad/s) with damping ratio `bodyDampingRatio`; the joints hold
  /// the bodies together by these links (a fixed joint's too).
  std::vector<UrdfBodyLink> bodyLinks{};
  double bodyFrequency = 0.0, bodyDampingRatio = 0.0;
  /// Every moving joint compensates gravity (Joint::compensateGravity): with holdJoints.
  bool compensateGravity = false;
  /// Object pairs (indices into objects) that do not touch each other.
  std::vector<std::array<int, 2>> noContact{};
  /// Objects [0, noContactWithin) (its links') touch none of each other (no
  /// selfCollision): one contact group, not every pair (ModelBuilder::excludeContactWithin).
  int noContactWithin = 0;
  /// One a kind of element robophi ignores (<gazebo>, <transmission>, <visual>, ...).
  std::vector<UrdfWarning> warnings{};
  /// The mass given to a notional base (kg).
  double notionalMass = 0.0;
  /// Its links' <visual> elements (display only), placed with it as Model::visuals.
  std::vector<UrdfVisual> visuals{};
};

/// Reads, checks and builds a URDF robot; throws UrdfError (file:line and the element or
/// value) for a file that cannot be imported, SpecError for a bad spec field.
UrdfRobot makeUrdfRobot(const UrdfSpec& spec);

/// roslaunch's substitution args in `text`: $(optenv NAME default...) is the environment
/// variable NAME's value or the default (the words after NAME, joined by spaces; may be
/// empty), $(env NAME) NAME's value. URDF attributes and a scene's URDF "file" and
/// "packagePaths" use it. Throws std::invalid_argument naming the argument for any other
/// command, or $(env NAME) with NAME unset.
std::string substituteRosArgs(std::string text);

/// Moves the whole robot (its particles, link frames and declared world values) by `offset` (m).
void translateUrdfRobot(UrdfRobot& robot, const Vec3& offset);

/// Where a placed robot is in a model.
struct PlacedUrdfRobot {
  /// (UrdfRobot::objects) where each object's particles are.
  std::vector<PlacedObject> objects{};
  /// (UrdfRobot::joints) index into Model::joints, -1 for a fixed joint.
  std::vector<std::int32_t> modelJoint{};
  /// (UrdfRobot::links) index into Model::bodies, -1 for a frame.
  std::vector<std::int32_t> body{};
};

/// Places the robot's objects, connectors and named joints, and its no-contact pairs, in
/// `builder` (its object names must be new).
PlacedUrdfRobot placeUrdfRobot(ModelBuilder& builder, const UrdfRobot& robot);

}  // namespace robophi::build
