#pragma once
/// \file
/// Kinematics of a multibody for robot programs (docs/python.md "Kinematics"): the
/// joints in a stable order with their limits, forward kinematics of any frame at
/// any q, geometric Jacobians of a point on a frame, a frame's spatial velocity and
/// damped least-squares inverse kinematics for a frame pose.
///
/// Names follow Drake's monogram notation: X_WF is frame F's pose in the world W,
/// p_FP a point P's position in F, V_WF F's spatial velocity in W. A Jacobian here
/// has 6 rows, the velocity of the point first and the frame's angular velocity
/// next (KDL's and MuJoCo's jacp over jacr), one column per rate of v.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "robophi/multibody.h"
#include "robophi/rotation.h"
#include "robophi/vec3.h"

namespace robophi {

/// One moving joint (revolute, prismatic or free), in the order of its rates in v.
struct MultibodyJointInfo {
  std::string name;
  /// The body it moves; its first coordinate in q and rate in v, and their counts.
  std::int32_t body = -1, qStart = 0, vStart = 0, positionCount = 0, velocityCount = 0;
  BodyJointKind kind = BodyJointKind::kRevolute;
  /// Limits (rad or m; ±infinity: none) and the bound on |τ| (N·m or N; infinity: none).
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  double effortLimit = std::numeric_limits<double>::infinity();
};

/// The moving joints in the order of their rates (a free base first when the tree has one).
std::vector<MultibodyJointInfo> movingJoints(const Multibody& multibody);

/// X_WF: frame `frame`'s pose at q (positionCount values). Throws std::out_of_range for
/// a bad frame index.
Pose calcFramePose(const Multibody& multibody, const double* q, std::int32_t frame);

/// The geometric Jacobian of the point P fixed to frame F at p_FP, at the configuration
/// `kinematics` holds (after updateKinematics): 6 × velocityCount, row-major, into J;
/// rows 0–2 the velocity of P in W, rows 3–5 F's angular velocity in W.
void calcFrameJacobian(const Multibody& multibody, const MultibodyKinematics& kinematics,
                       std::int32_t frame, const Vec3& p_FP, double* J);

/// F's spatial velocity at P (after updateKinematics and updateVelocities): angular the
/// angular velocity ω_WF, linear the velocity of the point P (p_FP in F), both in W.
/// Equal to J v with J from calcFrameJacobian.
SpatialVector calcFrameSpatialVelocity(const Multibody& multibody,
                                       const MultibodyKinematics& kinematics, std::int32_t frame,
                                       const Vec3& p_FP);

/// How inverse kinematics searches (damped least squares, Levenberg–Marquardt style).
struct InverseKinematicsSettings {
  /// Weight of the position error (1/m) and of the orientation error (1/rad); 0 leaves
  /// that part free (a position-only or orientation-only target), both >= 0, one > 0.
  double positionWeight = 1.0;
  double orientationWeight = 1.0;
  /// Initial damping λ of (JᵀJ + λ² I) (same units as the weighted error), > 0: raised
  /// when a step does not reduce the error, lowered when it does.
  double damping = 1e-2;
  /// Largest change of any coordinate in one iteration (rad or m), > 0.
  double maxStepSize = 0.5;
  /// Iterations per attempt, >= 1.
  int maxIterations = 100;
  /// Success: the position within positionTolerance (m) and the orientation within
  /// orientationTolerance (rad) of the target.
  double positionTolerance = 1e-6;
  double orientationTolerance = 1e-5;
  /// Further attempts from random configurations within the limits (±π for an
  /// unlimited revolute joint, ±1 m for an unlimited slide) when an attempt stalls
  /// short of the tolerances; >= 0.
  int restarts = 20;
  /// Seed of the restarts' configurations: the same seed gives the same answer.
  std::uint64_t seed = 1;
};

/// What inverse kinematics found: the best configuration of all attempts.
struct InverseKinematicsResult {
  /// (positionCount) the configuration, within the joints' limits.
  std::vector<double> q;
  /// Whether both errors are within their tolerances.
  bool success = false;
  /// |p_WF − p*| (m) and the angle of R_WFᵀ R* (rad) at q.
  double positionError = 0.0;
  double orientationError = 0.0;
  /// Iterations over all attempts, and the attempts made (1 + restarts used).
  int iterations = 0;
  int attempts = 0;
};

/// Finds q with X_WF(q) = X_WF_target, starting from q0 (positionCount values; limits
/// respected throughout). Throws std::invalid_argument for bad settings or sizes.
InverseKinematicsResult solveInverseKinematics(const Multibody& multibody, std::int32_t frame,
                                               const Pose& X_WF_target,
                                               const std::vector<double>& q0,
                                               const InverseKinematicsSettings& settings = {});

/// A configuration drawn uniformly within the joints' limits (see restarts above) from
/// a generator state, advanced; free joints keep q0's values.
std::vector<double> randomConfiguration(const Multibody& multibody, const std::vector<double>& q0,
                                        std::uint64_t& state);

}  // namespace robophi
