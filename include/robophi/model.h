#pragma once
/// \file
/// Model: everything that does not change during a step (MODEL §1).
/// Masses, radii, connector rest values and stiffnesses, objects and joints.
/// The mutable part (positions, velocities, forces) is State (state.h).

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "robophi/contact.h"
#include "robophi/multibody.h"
#include "robophi/vec3.h"
#include "robophi/visuals.h"

namespace robophi {

/// Index of a particle in the model's flat arrays.
using ParticleIndex = std::int32_t;
inline constexpr ParticleIndex kNoParticle = -1;

/// LS: linear spring/damper between particles a and b (MODEL §1, LS).
/// F_a = (-κ Δl - μ l̇) k̂, F_b = -F_a, energy ½ κ Δl².
struct LinearSpring {
  ParticleIndex a = kNoParticle;
  ParticleIndex b = kNoParticle;
  /// Rest length l0 (m), > 0.
  double restLength = 0.0;
  /// Stiffness κ (N/m), >= 0.
  double stiffness = 0.0;
  /// Damping μ (N·s/m), >= 0.
  double damping = 0.0;
};

/// TS: torsion spring/damper on the angle a-c-b, c the centre (MODEL §1, TS).
/// θ in [0, π]; energy ½ κ (θ - θ0)². With θ0 = π it keeps a, c, b collinear.
struct TorsionSpring {
  ParticleIndex a = kNoParticle;
  ParticleIndex c = kNoParticle;
  ParticleIndex b = kNoParticle;
  /// Rest angle θ0 (rad), in [0, π].
  double restAngle = 0.0;
  /// Stiffness κ (N·m/rad), >= 0.
  double stiffness = 0.0;
  /// Damping μ (N·m·s/rad), >= 0.
  double damping = 0.0;
};

/// JS: joint spring/damper, a TS with a reference particle d that orients the
/// angle (MODEL §1, JS). θ in [0, 2π) measured positive about n = (p_d - p_c)/|p_d - p_c|.
/// The force on d is zero when the arms lie in the plane through c normal to the
/// axis (as the joint builders make them). The spring acts on θ - θ0 wrapped into (-π, π].
struct JointSpring {
  ParticleIndex a = kNoParticle;
  ParticleIndex c = kNoParticle;
  ParticleIndex b = kNoParticle;
  ParticleIndex d = kNoParticle;
  /// Rest (target) angle θ0 (rad), in [0, 2π).
  double restAngle = 0.0;
  /// Stiffness κ (N·m/rad), >= 0; 0 for a passive ("switched off") joint.
  double stiffness = 0.0;
  /// Damping μ (N·m·s/rad), >= 0.
  double damping = 0.0;
};

/// A named group of particles made by one generator or listed in one scene object.
/// How contacts treat an object (docs/contact.md "What an object tells the
/// contacts"): set by the generator or builder that made it. The contact stage,
/// the step and the sensors read these, never the object's kind.
struct ContactRole {
  /// False: the object touches nothing (a goal's copy, a path's end, a URDF
  /// link's inertia carriers): no contact, no approach bound, no range reading.
  bool touches = true;
  /// True: each of its particles' contacts decide their friction on their own (a
  /// rope's links slide one by one); false: the object's contacts with one other
  /// body decide together, as one body (MODEL §3.3 "The three regimes").
  bool frictionPerParticle = false;
  /// False: its particles neither spin nor turn with their LS neighbours at a
  /// contact point (a rope's links; MODEL §3.3 "What turns a contact point").
  bool turns = true;
};

struct ObjectInfo {
  std::string name;
  /// Generator that made it: "rope", "bar", "plate", "box", "ball", "wheel", "particles".
  std::string kind;
  ParticleIndex firstParticle = 0;
  ParticleIndex particleCount = 0;
  /// Index into Model::materials (contact properties); 0 is the default material.
  std::int32_t material = 0;
  /// Its surface mesh (MODEL §3.8): Model::surfaceVertices[firstVertex,
  /// firstVertex + vertexCount) and surfaceTriangles[firstTriangle, ... +
  /// triangleCount). Without a mesh (counts 0) the object touches by its particles.
  std::int32_t firstVertex = 0, vertexCount = 0;
  std::int32_t firstTriangle = 0, triangleCount = 0;
  /// Half thickness of the surface (m), >= 0: 0 for a closed surface (a box's
  /// faces, outward normals), > 0 for a sheet (a plate's mid-surface, touched
  /// from both sides at this distance).
  double surfaceRadius = 0.0;
  /// The object is stiff enough to be treated as rigid by the contact search: its
  /// sphere tree moves as a whole (ContactSettings::rigidTreeMargin), no refit.
  bool rigid = false;
  /// Objects of one group (>= 0) never touch each other (a robot's links:
  /// build::ModelBuilder::excludeContactWithin): one id per object, where pairs
  /// would grow with the square of the links; -1: no group.
  std::int32_t contactGroup = -1;
  /// How contacts treat it (its builder's; never read from `kind`).
  ContactRole contact{};
};

/// A point of an object's outer surface embedded in its particles (MODEL §3.8):
/// x = Σ_k weight[k] p[particle[k]], Σ weight = 1 (affine weights, exact for any
/// affine motion, so rigid motions carry the surface exactly). A force F on the
/// vertex acts as weight[k] F on each particle: net force, torque and power kept.
struct SurfaceVertex {
  static constexpr int kMaxParticles = 8;
  /// Particles (model indices); unused slots are kNoParticle with weight 0.
  std::array<std::int32_t, kMaxParticles> particle{-1, -1, -1, -1, -1, -1, -1, -1};
  /// Weights (-), summing to 1; some are negative (extrapolation to the surface).
  std::array<double, kMaxParticles> weight{};
  /// The object the vertex belongs to.
  std::int32_t object = -1;
};

/// A triangle of an object's surface mesh: vertices (indices into
/// Model::surfaceVertices) counter-clockwise seen from outside.
struct SurfaceTriangle {
  std::array<std::int32_t, 3> vertex{-1, -1, -1};
  std::int32_t object = -1;
};

/// Contact properties of a material (used by the contact stage, MODEL §3).
struct Material {
  std::string name = "default";
  /// Collision rigidity κ_c (N/m). Stiffer needs a smaller step.
  double contactStiffness = 1.0e4;
  /// Collision damping μ_c (N·s/m).
  double contactDamping = 10.0;
  /// Static friction coefficient μ_s (-).
  double staticFriction = 0.5;
  /// Kinetic friction coefficient μ_k (-), <= μ_s.
  double kineticFriction = 0.4;
  /// Rolling resistance coefficient μ_r (-, MODEL §3.3): a rolling contact feels
  /// a torque μ_r r F_n against its rolling, r the rolling particle's radius
  /// (a pair takes the mean of its two materials). 0: rolls freely.
  double rollingResistance = 0.0;
};

/// Two materials in contact (docs/contact.md "Materials and pairs"): each is
/// half of the contact, so their stiffnesses and their dampings are in series
/// (κ_a κ_b / (κ_a + κ_b); 0 when both are 0); the friction coefficients are the
/// geometric means, the rolling resistance the mean. The one place this rule is
/// written: the contact stage's pair table and a scene's contact pairs (their
/// defaults) both take it from here.
Material combineMaterials(const Material& a, const Material& b);

/// A round body (MODEL §3.5, docs/contact.md "Round rims", "Round balls"): `count`
/// particles [first, first + count) that meet the environment as one rigid round
/// surface about their mass centre, instead of a polygon or lattice of spheres.
/// - A wheel's rim ring (sphereRadius 0): particles on a circle about particle
///   `hub`, the ring's centre on the axle; the surface is the torus they sweep.
/// - A ball (sphereRadius > 0, hub kNoParticle): the particles of a ball's
///   lattice; the surface is the sphere of radius sphereRadius (m) about their
///   mass centre.
/// - A cylinder wheel (sphereRadius > 0, axisParticle set: an imported robot's
///   wheel, docs/contact.md "Round wheels"): the particles of the wheel's body;
///   the surface is the cylinder of radius sphereRadius and half length
///   halfLength about the axis from particle `hub` to particle `axisParticle`
///   (both of the body), centred axialOffset (m) from the hub along it. It
///   meets the environment at its two edge circles.
/// Both a ball and a cylinder are rigid about their particles' mass centre with
/// a fixed radius (isSphere(): the contact stage's rigid round body).
struct RimRing {
  ParticleIndex first = 0;
  std::int32_t count = 0;
  ParticleIndex hub = kNoParticle;
  /// A ball's or a cylinder's outer radius (m), > 0; 0 for a wheel's ring.
  double sphereRadius = 0.0;
  /// A cylinder's axis particle (with `hub`), its half length (m, >= 0) and its
  /// centre's offset from the hub along the axis (m); kNoParticle: not a cylinder.
  ParticleIndex axisParticle = kNoParticle;
  double halfLength = 0.0, axialOffset = 0.0;

  bool isSphere() const { return sphereRadius > 0.0; }
  bool isCylinder() const { return axisParticle != kNoParticle; }
};

/// The kind of a named joint.
enum class JointKind : std::uint8_t {
  /// Revolute: a JS measures and drives the angle. Value in rad, [0, 2π).
  kRevolute,
  /// Prismatic: a TS at 180° keeps the slider on the line. Value in m: the
  /// distance from the origin particle to the slider along the line.
  kPrismatic,
};

/// A joint's motor and losses (MODEL §1.6): a generalized force Q on the joint's
/// position q — N·m about the axis for a revolute joint, N along the line for a
/// prismatic one; positive increases q — applied through the joint's own
/// connector particles as F_j = Q ∂q/∂p_j, so that the forces sum to zero, their
/// torques balance and its power is Q q̇.
///   motor:  τ = clamp(effort + rateGain (targetRate − q̇), ±effortLimit), and no
///           motor effort that would drive |q̇| beyond velocityLimit; its power
///           τ q̇ is work done from outside (EnergyTally::external);
///   losses: −damping q̇ − friction · clamp(q̇ / frictionVelocity, −1, 1), dissipated.
/// The defaults do nothing. Units: N·m or N, rad/s or m/s.
struct JointDrive {
  /// Commanded effort τ0 (N·m or N), finite.
  double effort = 0.0;
  /// Rate drive gain k_v (N·m·s/rad or N·s/m), >= 0, and its target rate q̇* (rad/s or m/s).
  double rateGain = 0.0, targetRate = 0.0;
  /// Bound on |τ| (N·m or N), > 0; infinity: none.
  double effortLimit = std::numeric_limits<double>::infinity();
  /// Velocity limit (rad/s or m/s), > 0; infinity: none.
  double velocityLimit = std::numeric_limits<double>::infinity();
  /// Viscous damping b (N·m·s/rad or N·s/m), >= 0.
  double damping = 0.0;
  /// Coulomb friction F_c (N·m or N), >= 0, reached at |q̇| = frictionVelocity
  /// (rad/s or m/s, > 0); below it the friction is viscous (slope F_c / frictionVelocity,
  /// which must stay below what the step resolves).
  double friction = 0.0, frictionVelocity = 0.01;
};

/// Bodies (indices into Model::bodies) in an order the sums over them keep: a run
/// of a buffer that lists may share. An imported chain's weight and subtree lists
/// (BodyLink::weightBodies, Joint::subtreeBodies: a link's body and every body
/// below it) are the suffixes of one run, so they take memory linear in its links
/// where a list of its own each took their square (build::placeUrdfRobot). Read as
/// a range; a vector assigned to it is a list of its own. The buffer never changes.
class BodyList {
 public:
  BodyList() = default;
  BodyList(std::vector<std::int32_t> bodies)  // NOLINT: a list of its own, implicitly
      : run_(std::make_shared<const std::vector<std::int32_t>>(std::move(bodies))),
        count_(run_->size()) {}
  /// [first, first + count) of `run`.
  BodyList(std::shared_ptr<const std::vector<std::int32_t>> run, std::size_t first,
           std::size_t count)
      : run_(std::move(run)), first_(first), count_(count) {}
  const std::int32_t* begin() const { return count_ == 0 ? nullptr : run_->data() + first_; }
  const std::int32_t* end() const { return begin() + count_; }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  std::int32_t operator[](std::size_t k) const { return begin()[k]; }
  void clear() { *this = BodyList(); }

 private:
  std::shared_ptr<const std::vector<std::int32_t>> run_;
  std::size_t first_ = 0, count_ = 0;
};

/// A named joint whose value is read at every step (joints.csv).
struct Joint {
  std::string name;
  JointKind kind = JointKind::kRevolute;
  /// Revolute: index into Model::jointSprings. Prismatic: index into Model::torsionSprings.
  std::int32_t connector = -1;
  /// Prismatic only: the LS (index into Model::linearSprings) that drives the
  /// slider's distance from the origin, or -1 if the joint is free along its line.
  std::int32_t driveSpring = -1;
  /// The raw value (jointValue: rad, or m) at which the joint's position q is 0
  /// (jointPosition). Builders set it to a revolute joint's angle as built (an
  /// arm's straight pose, a URDF robot's zero pose); a prismatic joint's is 0
  /// (its value is the distance from its origin) unless its builder says otherwise.
  double zero = 0.0;
  /// Its motor and losses (MODEL §1.6; World::setJointEffort, setJointDrive).
  JointDrive drive{};
  /// Revolute only: further particles of the child body (model indices) that the
  /// drive acts through besides the JS's b, each as the child arm of the JS's a,
  /// c, d, sharing the effort equally (MODEL §1.6): a wheel's motor spread over
  /// its rim, so that no single light particle carries the rate drive. Empty: b alone.
  std::vector<ParticleIndex> motorParticles{};
  /// Index into Model::bodyLinks of the body link that joins the joint's two bodies,
  /// or -1 (MODEL §1.7). When set, the joint's servo, motor and losses act as a wrench
  /// on the child body and its reaction on the parent, each spread over its particles
  /// as the rigid motion it causes, and the drive's rate q̇ is the bodies' relative
  /// rigid velocity: no connector particle carries the joint's torque alone. An
  /// imported URDF joint's (build::placeUrdfRobot).
  std::int32_t bodyLink = -1;
  /// With a body link or in a rigid tree: the servo (MODEL §1.7, docs/model.md §7)
  /// that World::setJointServo and setJointTarget set, instead of the JS's or the
  /// drive LS's: stiffness (N·m/rad or N/m) >= 0, damping (N·m·s/rad or N·s/m) >= 0,
  /// and the target as a raw value (jointValue: rad in [0, 2π) with a body link, the
  /// coordinate q* in a tree, or m).
  double servoStiffness = 0.0, servoDamping = 0.0, servoTarget = 0.0;
  /// With a body link: the bodies (Model::bodies) the joint carries — its child and
  /// every body below it — and whether its motor adds the effort that holds them
  /// against gravity (MODEL §1.7: −n·Σ (p̄_b − s) × M_b g, or −n·Σ M_b g; booked as
  /// the motor's work): gravity compensation, World::setGravityCompensation.
  BodyList subtreeBodies{};
  bool compensateGravity = false;
  /// A joint of a rigid tree (docs/model.md §7): the tree (index into
  /// Model::rigidTrees) and the body (index into its Multibody::bodies) whose joint
  /// it is, or -1. Its value is the tree's coordinate q itself (rad or m, not
  /// wrapped, zero 0), its rate the tree's; connector, driveSpring and bodyLink are
  /// unused. Its servo is servoStiffness, servoDamping and servoTarget (a
  /// coordinate q*); its drive acts on the tree's rate; compensateGravity adds the
  /// effort that holds the tree at q against gravity (ModelBuilder::addRigidTree
  /// makes these joints).
  std::int32_t tree = -1, treeBody = -1;
  bool actsThroughBodies() const { return bodyLink >= 0; }
  bool inTree() const { return tree >= 0; }
  /// Its servo: a revolute joint's JS, a body link's or tree joint's own, a
  /// prismatic joint's drive LS (none without one).
  bool hasServo() const {
    return inTree() || actsThroughBodies() || kind == JointKind::kRevolute || driveSpring >= 0;
  }
  /// Its value is an angle wrapped into [0, 2π) (a revolute joint of connectors).
  bool wraps() const { return kind == JointKind::kRevolute && !inTree(); }
};

/// A rigid body of particles (MODEL §1.7): a link of an imported robot. Its rest
/// shape is the particles' offsets from their mass centre as built; shape matching
/// pulls each particle towards where the body's best-fit rigid motion puts it,
/// f_i = m_i ω² (p̄ + R r_i − p_i), with damping of the motion relative to the rigid
/// one, so that the body stays rigid whatever its lattice's stiffness.
struct RigidGroup {
  std::string name;
  /// Its particles (model indices) and their rest offsets r_i (m) from the rest centre.
  std::vector<ParticleIndex> particles;
  std::vector<Vec3> rest;
  /// Shape matching's natural frequency ω (rad/s), >= 0 (0: none), and damping ratio
  /// ζ >= 0 (the relative motion's damping 2 ζ ω m_i, N·s/m).
  double frequency = 0.0, dampingRatio = 0.0;
};

/// What a body link leaves free between its two bodies.
enum class BodyLinkKind : std::uint8_t { kRevolute, kPrismatic, kFixed };

/// Two rigid bodies held together as a joint holds them (MODEL §1.7): a revolute
/// link keeps the joint point of each body together and their axes aligned (the
/// turn about the axis free), a prismatic one keeps the child's point on the
/// parent's line and the bodies' orientations equal (the slide free), a fixed one
/// locks all six. Penalty springs on the bodies' rigid motions (position error e:
/// −κ e − β ė at the point; orientation error θ: −κ_θ θ − β_θ θ̇), applied as a
/// wrench on the child and its reaction on the parent, each spread over the body's
/// particles as the rigid motion it causes.
struct BodyLink {
  BodyLinkKind kind = BodyLinkKind::kRevolute;
  /// Indices into Model::bodies.
  std::int32_t child = -1, parent = -1;
  /// The joint point and the unit axis in each body's rest frame (m; -), and a unit
  /// vector normal to the axis (the orientation lock of a prismatic or fixed link).
  Vec3 pointInChild{}, pointInParent{}, axisInChild{0, 0, 1}, axisInParent{0, 0, 1};
  Vec3 normalInChild{1, 0, 0}, normalInParent{1, 0, 0};
  /// Position: κ (N/m) and β (N·s/m); orientation: κ_θ (N·m/rad) and β_θ (N·m·s/rad); >= 0.
  double stiffness = 0.0, damping = 0.0, angularStiffness = 0.0, angularDamping = 0.0;
  /// Indices into Model::bodies of the bodies whose weight the link carries (the child
  /// and every body below it), or empty. MODEL §1.7, the weight preload: the link adds
  /// the static wrench that holds them against gravity, less its part along the free
  /// direction (a joint's gravity compensation), so that its springs hold a static
  /// robot with no gap; its power is booked as driving work.
  BodyList weightBodies{};
};

/// A particle that carries a rigid body's contact surface (docs/model.md §7): a
/// fixed particle of the model (inverse mass 0) that the body moves; the force
/// and torque the evaluation finds on it act on the body.
struct BodyParticle {
  ParticleIndex particle = kNoParticle;
  /// Index into the tree's Multibody::bodies.
  std::int32_t body = 0;
  /// Its position in the body's frame p_BP (m).
  Vec3 p_BP{};
};

/// A tree of rigid bodies in reduced coordinates (docs/model.md §7): its bodies'
/// exact mass properties and joints, the particles that carry its contact surface
/// (only its <collision> geometry), and what drives it. Its coordinates and rates
/// are State::treePositions and treeVelocities.
struct RigidTree {
  Multibody multibody;
  std::vector<BodyParticle> particles;
  /// (velocityCount) the joint (index into Model::joints) of each rate, or -1 (a
  /// free base's): its servo, drive and gravity compensation drive the rate
  /// (ModelBuilder::addRigidTree sets it).
  std::vector<std::int32_t> jointOfRate;
};

/// The model: particles as flat arrays, connectors as small structs.
struct Model {
  // Particles. Every array has particleCount() entries.
  /// Mass m_i (kg), > 0.
  std::vector<double> mass;
  /// 1 / m_i (1/kg); 0 for a fixed particle, which never moves.
  std::vector<double> inverseMass;
  /// Radius r_i (m), > 0: the particle's extent for contact and display.
  std::vector<double> radius;
  /// Linear damping c_i (N·s/m): force -c_i v_i, e.g. a medium's drag.
  std::vector<double> linearDamping;
  /// Index into objects of the object each particle belongs to.
  std::vector<std::int32_t> objectOf;

  // Connectors.
  std::vector<LinearSpring> linearSprings;
  std::vector<TorsionSpring> torsionSprings;
  std::vector<JointSpring> jointSprings;
  /// Trees of rigid bodies (docs/model.md §7).
  std::vector<RigidTree> rigidTrees;
  /// Rigid bodies of particles and the links between them (MODEL §1.7).
  std::vector<RigidGroup> bodies;
  std::vector<BodyLink> bodyLinks;

  /// Gravity g (m/s²), applied as m_i g to every particle.
  Vec3 gravity{0.0, 0.0, -9.81};

  std::vector<ObjectInfo> objects;
  /// Wheel rims and balls with a round contact surface (RimRing).
  std::vector<RimRing> rims;
  std::vector<Material> materials{Material{}};
  std::vector<Joint> joints;
  /// Surface meshes of the objects that have one (MODEL §3.8; ObjectInfo ranges).
  std::vector<SurfaceVertex> surfaceVertices;
  std::vector<SurfaceTriangle> surfaceTriangles;

  /// What particles collide with besides each other, and the medium (MODEL §3).
  Environment environment;
  /// How contacts are found and computed (docs/contact.md).
  ContactSettings contact;
  /// Object pairs {a, b}, a < b, whose particles never touch each other (a
  /// robot's jointed links: build::ModelBuilder::excludeContact), sorted ascending;
  /// besides the objects of one ObjectInfo::contactGroup.
  std::vector<std::array<std::int32_t, 2>> noContactPairs;

  /// (particleCount, or empty: none) the rigid tree (index into rigidTrees) that
  /// carries each particle, or -1 (ModelBuilder::addRigidTree sets it).
  std::vector<std::int32_t> carriedBy;

  /// What the robots look like (URDF <visual>; robophi/visuals.h): for display only.
  std::vector<VisualShape> visuals;

  ParticleIndex particleCount() const { return static_cast<ParticleIndex>(mass.size()); }
  bool isFixed(ParticleIndex i) const { return inverseMass[i] == 0.0; }
  /// A fixed particle that a rigid tree's body moves (docs/model.md §7).
  bool isCarried(ParticleIndex i) const {
    return !carriedBy.empty() && carriedBy[static_cast<std::size_t>(i)] >= 0;
  }
  /// The particle moves under the loads on it: free, or carried by a rigid tree.
  bool moves(ParticleIndex i) const { return inverseMass[i] != 0.0 || isCarried(i); }

  /// Appends a particle and returns its index. A fixed particle gets inverseMass 0.
  ParticleIndex addParticle(double particleMass, double particleRadius, bool fixed,
                            std::int32_t object, double damping = 0.0);
  /// Appends an object covering no particle yet; returns its index.
  std::int32_t addObject(std::string name, std::string kind, std::int32_t material = 0);
};

/// Checks the model's internal consistency (array sizes, indices in range,
/// positive masses and radii, non-negative stiffness). Returns an empty string if
/// it holds, otherwise the first problem found, naming the item and the value.
std::string checkModel(const Model& model);

/// Checks a joint drive (MODEL §1.6): finite effort and target rate, gains and
/// losses >= 0, limits and friction velocity > 0. Returns an empty string if it
/// holds, otherwise the problem, naming the field and the value.
std::string checkJointDrive(const JointDrive& drive);

/// Checks connector number k against a model of `particleCount` particles
/// (indices in range and distinct, rest value and stiffness valid). Returns an
/// empty string if it holds, otherwise the problem.
std::string checkConnector(const LinearSpring& spring, std::size_t k, ParticleIndex particleCount);
std::string checkConnector(const TorsionSpring& spring, std::size_t k, ParticleIndex particleCount);
std::string checkConnector(const JointSpring& spring, std::size_t k, ParticleIndex particleCount);

}  // namespace robophi
