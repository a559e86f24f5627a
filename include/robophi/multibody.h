#pragma once
/// \file
/// Rigid bodies that are rigid (docs/model.md §7): a tree of rigid bodies in
/// reduced coordinates, each with its exact mass, centre of mass and inertia
/// tensor, moved by one joint (weld, revolute, prismatic or free) from its
/// parent. Joints hold exactly (no joint error to correct), limits are hard
/// stops, and joint damping and servos are integrated implicitly, so that gains
/// a MuJoCo user would use at 1 kHz are stable.
///
/// Conventions (Featherstone's spatial algebra in world coordinates, at the world
/// origin): a spatial motion is (ω, v_O), ω the angular velocity and v_O the
/// velocity of the body-fixed point at the world origin; a spatial force is
/// (n_O, f), the moment about the world origin and the force. Names follow
/// Drake's monogram notation: X_WB is body B's pose in the world W, p_WP a
/// point's position in W.
///
/// Generalized coordinates: a revolute joint's q (rad) is the turn about its
/// axis, a prismatic joint's (m) the slide along it, both from the joint frame
/// X_PJ; a free joint has q = (x, y, z, qw, qx, qy, qz) (the body origin in W and
/// its orientation) and v = (ω_W, v_WBo): the angular velocity and the velocity
/// of the body's origin, both in W.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "robophi/rotation.h"
#include "robophi/vec3.h"

namespace robophi {

/// How a body moves relative to its parent.
enum class BodyJointKind : std::uint8_t {
  /// No motion: a body welded to the world (a robot's fixed base). A body welded to
  /// another body is merged into it when the model is made.
  kWeld,
  /// A turn about the joint axis (rad).
  kRevolute,
  /// A slide along the joint axis (m).
  kPrismatic,
  /// Six degrees of freedom (a floating base).
  kFree,
  /// A ball (spherical) joint: three turns about the joint frame's origin. q is the
  /// unit quaternion (w, x, y, z) of B's rotation in J (MuJoCo's ball qpos), v the
  /// body's angular velocity relative to the parent in J's axes (rad/s). Passive:
  /// no servo, limit, damping or armature acts on it.
  kBall,
};

/// A body's mass properties in its own frame B.
struct BodyMassProperties {
  /// Mass m (kg), > 0.
  double mass = 0.0;
  /// Centre of mass p_BBcm (m).
  Vec3 centerOfMass{};
  /// Rotational inertia about the centre of mass, expressed in B (kg·m²),
  /// symmetric positive definite with the triangle inequalities.
  Mat3 inertia = Mat3::zero();
};

/// A spatial motion (ω, v_O) or force (n_O, f), in world coordinates.
struct SpatialVector {
  Vec3 angular{};
  Vec3 linear{};
};

/// One rigid body of a multibody and the joint that moves it.
struct MultibodyBody {
  std::string name;
  /// The parent body's index (earlier in the list), or -1: the world.
  std::int32_t parent = -1;
  BodyJointKind joint = BodyJointKind::kWeld;
  std::string jointName;
  /// The joint frame J in the parent's frame P (the world's for parent -1), as the
  /// body's frame B sits when q = 0 (a free joint: the initial pose when its q is
  /// neutral).
  Pose X_PJ{};
  /// The joint axis, unit, in J (= B): revolute and prismatic joints.
  Vec3 axis{1, 0, 0};
  BodyMassProperties mass{};
  /// Joint limits (rad or m): hard stops, lower <= upper; ±infinity: none.
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  /// Viscous damping b (N·m·s/rad or N·s/m), >= 0: integrated implicitly.
  double damping = 0.0;
  /// Coulomb friction (N·m or N), >= 0: a bounded impulse that stops the joint.
  double friction = 0.0;
  /// Bound on the joint's actuation |τ| (N·m or N), > 0; infinity: none.
  double effortLimit = std::numeric_limits<double>::infinity();
  /// Rotor inertia added to the joint's diagonal (kg·m² or kg), >= 0.
  double armature = 0.0;
  /// Set by finalize(): the first of its coordinates in q and of its rates in v.
  std::int32_t qStart = 0, vStart = 0;
};

/// A named frame fixed to a body: a URDF link (merged into the body it is welded to,
/// or the body's own frame), a tool point.
struct MultibodyFrame {
  std::string name;
  std::int32_t body = 0;
  /// The frame F in the body's frame B.
  Pose X_BF{};
};

/// A tree of rigid bodies (the model: nothing here changes during a run).
struct Multibody {
  std::string name;
  std::vector<MultibodyBody> bodies;
  std::vector<MultibodyFrame> frames;
  /// Set by finalize(): the sizes of q and v.
  std::int32_t positionCount = 0, velocityCount = 0;
  /// Set by finalize(), (velocityCount): each rate's body, and the rate its
  /// motion builds on (the previous rate of the same joint, or the last rate of
  /// the nearest moving ancestor; -1: none), the sparsity of the mass matrix.
  std::vector<std::int32_t> dofBody, dofParent;

  /// The index of a frame or body by name; -1 if none.
  std::int32_t frameIndex(const std::string& frameName) const;
  std::int32_t bodyIndex(const std::string& bodyName) const;
};

/// Checks a multibody and sets its counts and indices. Throws std::invalid_argument
/// naming the body, the field and the value.
void finalize(Multibody& multibody);

/// The joint's number of coordinates and rates.
int positionCountOf(BodyJointKind kind);
int velocityCountOf(BodyJointKind kind);

/// q at which every joint reads 0, or the limit nearest 0 when 0 is outside them (a
/// free joint: its X_PJ).
std::vector<double> neutralConfiguration(const Multibody& multibody);

/// What the algorithms compute at a configuration and reuse: poses, the joints'
/// motion subspaces, the bodies' spatial inertias and velocities, all in W.
struct MultibodyKinematics {
  /// (bodies) X_WB.
  std::vector<Pose> X_WB;
  /// (velocityCount) the motion each rate causes: column k of the motion subspace S.
  std::vector<SpatialVector> motion;
  /// (bodies) spatial velocity of each body (set by updateVelocities()).
  std::vector<SpatialVector> velocity;
  /// (velocityCount) Ṡ q̇ per rate's joint summed per body (set by updateVelocities()):
  /// the velocity-product acceleration each body's joint adds.
  std::vector<SpatialVector> biasAcceleration;
  /// (bodies) mass m, first moment h = m c and rotational inertia about the world
  /// origin I_O, in W.
  std::vector<double> mass;
  std::vector<Vec3> firstMoment;
  std::vector<Mat3> inertiaAtOrigin;
};

/// Poses, motion subspaces and inertias at q (positionCount values).
void updateKinematics(const Multibody& multibody, const double* q, MultibodyKinematics& kinematics);
/// Velocities and velocity-product terms at v (after updateKinematics at the same q).
void updateVelocities(const Multibody& multibody, const double* v, MultibodyKinematics& kinematics);

/// The pose of a frame in W.
Pose framePose(const Multibody& multibody, const MultibodyKinematics& kinematics,
               std::int32_t frame);

/// The geometric Jacobian of a point fixed to `body` at p_WP (in W): the rows of
/// its velocity (3 × velocityCount, row-major, into `translational`) and of the
/// body's angular velocity (3 × velocityCount, into `rotational`; may be null).
void pointJacobian(const Multibody& multibody, const MultibodyKinematics& kinematics,
                   std::int32_t body, const Vec3& p_WP, double* translational, double* rotational);

/// The velocity of a point fixed to `body` at p_WP, in W.
Vec3 pointVelocity(const MultibodyKinematics& kinematics, std::int32_t body, const Vec3& p_WP);

/// Inverse dynamics (recursive Newton–Euler): the generalized forces τ (velocityCount)
/// that give accelerations a at (q, v) under gravity g (m/s², in W) with the
/// external wrenches on the bodies (spatial forces in W, one per body; may be
/// null). With a = 0 and no wrenches: the bias forces (MuJoCo's qfrc_bias), with
/// also v = 0: the gravity forces.
void inverseDynamics(const Multibody& multibody, const MultibodyKinematics& kinematics,
                     const double* a, const Vec3& gravity, const SpatialVector* externalWrench,
                     double* tau);

/// Inverse dynamics as above, with what it passes from body to body: per body (may be
/// null each), its spatial acceleration A_b with gravity as the world's acceleration
/// −g (so that A_b's linear part at a point is that point's acceleration less g: what an
/// accelerometer fixed there reads), and the spatial force its joint transmits from the
/// parent to the body and everything below it (about the world origin, in W): the
/// wrench a force/torque sensor in the joint reads (MuJoCo's cfrc_int).
void inverseDynamics(const Multibody& multibody, const MultibodyKinematics& kinematics,
                     const double* a, const Vec3& gravity, const SpatialVector* externalWrench,
                     double* tau, SpatialVector* bodyAcceleration, SpatialVector* jointWrench);

/// Forward dynamics: the accelerations a (velocityCount) that the generalized forces τ
/// give at (q, v) under gravity with the external wrenches (may be null): M a = τ − c
/// + Jᵀ f, armature on M's diagonal (MuJoCo's qacc without constraints).
void forwardDynamics(const Multibody& multibody, const MultibodyKinematics& kinematics,
                     const double* tau, const Vec3& gravity, const SpatialVector* externalWrench,
                     double* a);

/// The joint-space mass matrix M(q) (velocityCount², row-major; composite rigid bodies).
void massMatrix(const Multibody& multibody, const MultibodyKinematics& kinematics, double* M);

/// x ← (M(q) + A)⁻¹ x (velocityCount), A the joints' armature on the diagonal: the
/// rates an impulse Jᵀ p gives, or forwardDynamics' solve (the tree's sparse factor).
void solveMassMatrix(const Multibody& multibody, const MultibodyKinematics& kinematics, double* x);

/// ½ vᵀ M v (J), from the bodies' velocities (after updateVelocities).
double kineticEnergy(const MultibodyKinematics& kinematics);
/// −Σ m g·c (J): the bodies' gravitational energy.
double gravitationalEnergy(const MultibodyKinematics& kinematics, const Vec3& gravity);
/// Σ I_b V_b: the total spatial momentum about the world origin (angular, linear).
SpatialVector spatialMomentum(const MultibodyKinematics& kinematics);

/// q ⊕ v dt: coordinates advanced at the rates v for dt (a free joint's
/// orientation on the unit quaternions, exactly).
void integrateConfiguration(const Multibody& multibody, double* q, const double* v, double dt);

/// What drives a multibody during a step, per rate (velocityCount each; empty: zero).
struct MultibodyInputs {
  /// Generalized forces applied as given (N·m or N): motors, gravity compensation.
  std::vector<double> effort;
  /// A servo per rate, τ = −κ (q − q*) − β (q̇ − q̇*) clamped to the effort limit,
  /// integrated implicitly: κ (N·m/rad or N/m), β (N·m·s/rad or N·s/m), q*, q̇*.
  std::vector<double> servoStiffness, servoDamping, servoTarget, servoTargetRate;
  /// A bound on |effort + servo| per rate (N·m or N), > 0, besides the joint's own
  /// effortLimit (the smaller holds); empty: the joint's alone. A velocity-limited
  /// motor is a rate servo bounded by its effort.
  std::vector<double> effortLimit;
  /// External wrenches on the bodies (spatial forces in W; empty: none): contacts.
  std::vector<SpatialVector> wrench;
};

/// Scratch of the step (sized on first use); any workspace gives the same result.
struct MultibodyWorkspace {
  MultibodyKinematics kinematics;
  /// The inputs a caller composes for a step (the world's tree stage), kept to reuse.
  MultibodyInputs inputs;
  std::vector<double> mass, massMatrix, rhs, tau, scratch, servo, velocityFree, delassus, impulse,
      column;
  std::vector<std::int32_t> constrained;
};

/// What a step did, for the energy account.
struct MultibodyStepReport {
  /// Work done by the efforts and the servos' targets (J): energy from outside.
  double inputWork = 0.0;
  /// Energy the joints' damping, friction and hard stops, the servos' dampers and
  /// their implicit springs' step (½ κ δ² v⁺² a step) removed (J), >= 0 up to the
  /// step's own error. The servos' targets' rates do work (β q̇* v⁺ δ) booked as inputWork.
  double dissipated = 0.0;
  /// Of `dissipated`, the implicit point loads' scheme loss (J): ½ δ² u⁺ᵀ K u⁺ and
  /// the damper's work at v⁺ beyond the trapezoid rule's, integration error.
  double implicitLoss = 0.0;
  /// Number of joints at a hard stop or held by friction after the step.
  int constrainedJoints = 0;
};

/// One step of semi-implicit Euler: v⁺ = v + dt M⁻¹ (τ − c(q, v)) with the joints'
/// damping and servos implicit ((M + dt B + dt² K) v⁺ = ...), hard stops and
/// joint friction as bounded impulses on v⁺, then q⁺ = q ⊕ v⁺ dt.
MultibodyStepReport stepMultibody(const Multibody& multibody, std::vector<double>& q,
                                  std::vector<double>& v, const MultibodyInputs& inputs, double dt,
                                  const Vec3& gravity, MultibodyWorkspace& workspace);

}  // namespace robophi
