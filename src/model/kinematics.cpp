// Kinematics for robot programs (include/robophi/kinematics.h): joints in rate
// order, frame poses, Jacobians and velocities, damped least-squares IK.
#include "robophi/kinematics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace robophi {

std::vector<MultibodyJointInfo> movingJoints(const Multibody& multibody) {
  std::vector<MultibodyJointInfo> joints;
  for (std::size_t b = 0; b < multibody.bodies.size(); ++b) {
    const MultibodyBody& body = multibody.bodies[b];
    if (body.joint == BodyJointKind::kWeld) continue;
    MultibodyJointInfo j;
    j.name = body.jointName;
    j.body = static_cast<std::int32_t>(b);
    j.qStart = body.qStart;
    j.vStart = body.vStart;
    j.positionCount = positionCountOf(body.joint);
    j.velocityCount = velocityCountOf(body.joint);
    j.kind = body.joint;
    j.lower = body.lower;
    j.upper = body.upper;
    j.effortLimit = body.effortLimit;
    joints.push_back(j);
  }
  return joints;
}

Pose calcFramePose(const Multibody& multibody, const double* q, std::int32_t frame) {
  if (frame < 0 || frame >= static_cast<std::int32_t>(multibody.frames.size()))
    throw std::out_of_range("frame index " + std::to_string(frame) + " out of range (" +
                            std::to_string(multibody.frames.size()) + " frames)");
  MultibodyKinematics kinematics;
  updateKinematics(multibody, q, kinematics);
  return framePose(multibody, kinematics, frame);
}

void calcFrameJacobian(const Multibody& multibody, const MultibodyKinematics& kinematics,
                       std::int32_t frame, const Vec3& p_FP, double* J) {
  const MultibodyFrame& f = multibody.frames.at(static_cast<std::size_t>(frame));
  const Vec3 p_WP = framePose(multibody, kinematics, frame) * p_FP;
  const std::size_t nv = static_cast<std::size_t>(multibody.velocityCount);
  pointJacobian(multibody, kinematics, f.body, p_WP, J, J + 3 * nv);
}

SpatialVector calcFrameSpatialVelocity(const Multibody& multibody,
                                       const MultibodyKinematics& kinematics, std::int32_t frame,
                                       const Vec3& p_FP) {
  const MultibodyFrame& f = multibody.frames.at(static_cast<std::size_t>(frame));
  const Vec3 p_WP = framePose(multibody, kinematics, frame) * p_FP;
  return {kinematics.velocity[static_cast<std::size_t>(f.body)].angular,
          pointVelocity(kinematics, f.body, p_WP)};
}

namespace {

// splitmix64: a portable generator, so that a seed gives the same restarts everywhere.
double uniform01(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

// A joint's search range: its limits, or ±π (a turn) / ±1 m (a slide) when it has none.
std::array<double, 2> searchRange(const MultibodyBody& body) {
  const double span = body.joint == BodyJointKind::kRevolute ? std::numbers::pi : 1.0;
  return {std::isfinite(body.lower) ? body.lower : -span,
          std::isfinite(body.upper) ? body.upper : span};
}

// The weighted error e = [w_p (p* − p); w_o log(R* Rᵀ)] at q, and its two norms.
struct PoseError {
  std::array<double, 6> e{};
  double position = 0.0, orientation = 0.0;
  double cost() const {
    double c = 0.0;
    for (double x : e) c += x * x;
    return c;
  }
};

PoseError poseError(const Pose& X_WF, const Pose& target, const InverseKinematicsSettings& s) {
  const Vec3 dp = target.translation - X_WF.translation;
  const Vec3 dr = rotationVector(target.rotation * transpose(X_WF.rotation));
  PoseError err;
  err.e = {s.positionWeight * dp.x,    s.positionWeight * dp.y,    s.positionWeight * dp.z,
           s.orientationWeight * dr.x, s.orientationWeight * dr.y, s.orientationWeight * dr.z};
  err.position = norm(dp);
  err.orientation = norm(dr);
  return err;
}

bool reached(const PoseError& err, const InverseKinematicsSettings& s) {
  return (s.positionWeight == 0.0 || err.position <= s.positionTolerance) &&
         (s.orientationWeight == 0.0 || err.orientation <= s.orientationTolerance);
}

// How far from the target, in tolerances (the worse of the two parts that count).
double shortfall(const PoseError& err, const InverseKinematicsSettings& s) {
  return std::max(s.positionWeight > 0.0 ? err.position / s.positionTolerance : 0.0,
                  s.orientationWeight > 0.0 ? err.orientation / s.orientationTolerance : 0.0);
}

// Solves A x = b for a symmetric positive definite 6×6 A (Cholesky, in place).
std::array<double, 6> solve6(std::array<double, 36> A, std::array<double, 6> b) {
  for (int j = 0; j < 6; ++j) {
    double d = A[j * 6 + j];
    for (int k = 0; k < j; ++k) d -= A[j * 6 + k] * A[j * 6 + k];
    const double l = std::sqrt(std::max(d, 1e-300));
    A[j * 6 + j] = l;
    for (int i = j + 1; i < 6; ++i) {
      double s = A[i * 6 + j];
      for (int k = 0; k < j; ++k) s -= A[i * 6 + k] * A[j * 6 + k];
      A[i * 6 + j] = s / l;
    }
  }
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < i; ++k) b[i] -= A[i * 6 + k] * b[k];
    b[i] /= A[i * 6 + i];
  }
  for (int i = 5; i >= 0; --i) {
    for (int k = i + 1; k < 6; ++k) b[i] -= A[k * 6 + i] * b[k];
    b[i] /= A[i * 6 + i];
  }
  return b;
}

// Clamps every one-coordinate joint into its limits.
void clampToLimits(const Multibody& multibody, std::vector<double>& q) {
  for (const MultibodyBody& body : multibody.bodies)
    if (velocityCountOf(body.joint) == 1) {
      double& x = q[static_cast<std::size_t>(body.qStart)];
      x = std::clamp(x, body.lower, body.upper);
    }
}

class IkAttempt {
 public:
  IkAttempt(const Multibody& multibody, std::int32_t frame, const Pose& target,
            const InverseKinematicsSettings& settings)
      : mb_(multibody),
        frame_(frame),
        target_(target),
        s_(settings),
        nv_(static_cast<std::size_t>(multibody.velocityCount)),
        J_(6 * nv_),
        dq_(nv_) {}

  // Runs one attempt from q (changed in place); returns its error at the end.
  PoseError run(std::vector<double>& q, int& iterations) {
    clampToLimits(mb_, q);
    PoseError err = errorAt(q);
    double lambda = s_.damping;
    for (int it = 0; it < s_.maxIterations && !reached(err, s_); ++it) {
      ++iterations;
      step(q, err, lambda);
      std::vector<double> trial = q;
      integrateConfiguration(mb_, trial.data(), dq_.data(), 1.0);
      clampToLimits(mb_, trial);
      const PoseError trialErr = errorAt(trial);
      if (trialErr.cost() < err.cost()) {
        q.swap(trial);
        err = trialErr;
        lambda = std::max(lambda * 0.3, 1e-12);
      } else {
        lambda *= 10.0;
        if (lambda > 1e6) break;  // stalled: a local minimum or the limits
      }
    }
    return err;
  }

 private:
  PoseError errorAt(const std::vector<double>& q) {
    updateKinematics(mb_, q.data(), kin_);
    return poseError(framePose(mb_, kin_, frame_), target_, s_);
  }

  // dq = Jᵀ (J Jᵀ + λ² I)⁻¹ e with the weighted J at the last errorAt; columns of
  // joints at a limit that the step would push further out are dropped.
  void step(const std::vector<double>& q, const PoseError& err, double lambda) {
    updateKinematics(mb_, q.data(), kin_);
    calcFrameJacobian(mb_, kin_, frame_, {}, J_.data());
    for (std::size_t c = 0; c < nv_; ++c) {
      for (std::size_t r = 0; r < 3; ++r) J_[r * nv_ + c] *= s_.positionWeight;
      for (std::size_t r = 3; r < 6; ++r) J_[r * nv_ + c] *= s_.orientationWeight;
    }
    for (int pass = 0; pass < 2; ++pass) {
      std::array<double, 36> A{};
      for (std::size_t i = 0; i < 6; ++i)
        for (std::size_t j = 0; j < 6; ++j) {
          double sum = i == j ? lambda * lambda : 0.0;
          for (std::size_t c = 0; c < nv_; ++c) sum += J_[i * nv_ + c] * J_[j * nv_ + c];
          A[i * 6 + j] = sum;
        }
      const std::array<double, 6> y = solve6(A, err.e);
      double largest = 0.0;
      for (std::size_t c = 0; c < nv_; ++c) {
        double x = 0.0;
        for (std::size_t r = 0; r < 6; ++r) x += J_[r * nv_ + c] * y[r];
        dq_[c] = x;
        largest = std::max(largest, std::abs(x));
      }
      if (largest > s_.maxStepSize)
        for (double& x : dq_) x *= s_.maxStepSize / largest;
      bool dropped = false;
      for (const MultibodyBody& body : mb_.bodies) {
        if (velocityCountOf(body.joint) != 1) continue;
        const auto c = static_cast<std::size_t>(body.vStart);
        const double x = q[static_cast<std::size_t>(body.qStart)];
        if ((x <= body.lower && dq_[c] < 0.0) || (x >= body.upper && dq_[c] > 0.0)) {
          for (std::size_t r = 0; r < 6; ++r) dropped |= J_[r * nv_ + c] != 0.0;
          for (std::size_t r = 0; r < 6; ++r) J_[r * nv_ + c] = 0.0;
        }
      }
      if (!dropped) return;
    }
  }

  const Multibody& mb_;
  std::int32_t frame_;
  Pose target_;
  const InverseKinematicsSettings& s_;
  std::size_t nv_;
  MultibodyKinematics kin_;
  std::vector<double> J_, dq_;
};

}  // namespace

std::vector<double> randomConfiguration(const Multibody& multibody, const std::vector<double>& q0,
                                        std::uint64_t& state) {
  std::vector<double> q = q0;
  for (const MultibodyBody& body : multibody.bodies) {
    if (velocityCountOf(body.joint) != 1) continue;
    const auto [low, high] = searchRange(body);
    q[static_cast<std::size_t>(body.qStart)] = low + (high - low) * uniform01(state);
  }
  return q;
}

InverseKinematicsResult solveInverseKinematics(const Multibody& multibody, std::int32_t frame,
                                               const Pose& X_WF_target,
                                               const std::vector<double>& q0,
                                               const InverseKinematicsSettings& settings) {
  const InverseKinematicsSettings& s = settings;
  if (frame < 0 || frame >= static_cast<std::int32_t>(multibody.frames.size()))
    throw std::invalid_argument("inverse kinematics: frame index " + std::to_string(frame) +
                                " out of range (" + std::to_string(multibody.frames.size()) +
                                " frames)");
  if (q0.size() != static_cast<std::size_t>(multibody.positionCount))
    throw std::invalid_argument("inverse kinematics: q0 has " + std::to_string(q0.size()) +
                                " values, expected " + std::to_string(multibody.positionCount));
  if (!(s.positionWeight >= 0.0) || !(s.orientationWeight >= 0.0) ||
      !(s.positionWeight + s.orientationWeight > 0.0) || !(s.damping > 0.0) ||
      !(s.maxStepSize > 0.0) || s.maxIterations < 1 || !(s.positionTolerance > 0.0) ||
      !(s.orientationTolerance > 0.0) || s.restarts < 0)
    throw std::invalid_argument(
        "inverse kinematics: weights must be >= 0 (one > 0), damping, step size and tolerances "
        "> 0, maxIterations >= 1, restarts >= 0");
  InverseKinematicsResult best;
  double bestShortfall = std::numeric_limits<double>::infinity();
  std::uint64_t state = s.seed;
  IkAttempt attempt(multibody, frame, X_WF_target, s);
  for (int a = 0; a <= s.restarts; ++a) {
    std::vector<double> q = a == 0 ? q0 : randomConfiguration(multibody, q0, state);
    ++best.attempts;
    const PoseError err = attempt.run(q, best.iterations);
    if (shortfall(err, s) < bestShortfall) {
      bestShortfall = shortfall(err, s);
      best.q = q;
      best.positionError = err.position;
      best.orientationError = err.orientation;
      best.success = reached(err, s);
    }
    if (best.success) break;
  }
  return best;
}

}  // namespace robophi
