// A tree of rigid bodies in reduced coordinates (include/robophi/multibody.h,
// docs/model.md §7): kinematics, recursive Newton–Euler, composite rigid bodies,
// the mass matrix's tree factorization, and the semi-implicit step with implicit
// joint damping and servos, hard stops and joint friction.
#include "robophi/multibody.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "model/multibody_contacts.h"

namespace robophi {

namespace {

std::string describe(const Multibody& multibody, std::size_t body) {
  return "multibody '" + multibody.name + "', body " + std::to_string(body) + " '" +
         multibody.bodies[body].name + "'";
}

// Spatial motion cross product v ×m m.
SpatialVector crossMotion(const SpatialVector& v, const SpatialVector& m) {
  return {cross(v.angular, m.angular), cross(v.angular, m.linear) + cross(v.linear, m.angular)};
}

// Spatial force cross product v ×f f.
SpatialVector crossForce(const SpatialVector& v, const SpatialVector& f) {
  return {cross(v.angular, f.angular) + cross(v.linear, f.linear), cross(v.angular, f.linear)};
}

// I V for a body of mass m, first moment h = m c and inertia I_O about the origin.
SpatialVector applyInertia(double m, const Vec3& h, const Mat3& inertiaAtOrigin,
                           const SpatialVector& v) {
  return {inertiaAtOrigin * v.angular + cross(h, v.linear), m * v.linear - cross(h, v.angular)};
}

double dotMotionForce(const SpatialVector& m, const SpatialVector& f) {
  return dot(m.angular, f.angular) + dot(m.linear, f.linear);
}

SpatialVector operator+(const SpatialVector& a, const SpatialVector& b) {
  return {a.angular + b.angular, a.linear + b.linear};
}

SpatialVector operator*(const SpatialVector& a, double s) { return {a.angular * s, a.linear * s}; }

bool isRotation(const Mat3& r) {
  const Mat3 e = transpose(r) * r - Mat3::identity();
  double worst = 0.0;
  for (const auto& row : e.m)
    for (double x : row) worst = std::max(worst, std::abs(x));
  return worst < 1e-9;
}

// The tree factorization of H = Lᵀ D L in place (Featherstone, RBDA §6.5): L unit
// lower triangular in the entries H[k][i], i an ancestor of k, D on the diagonal.
void factorTree(double* H, int n, const std::vector<std::int32_t>& parent) {
  for (int k = n - 1; k >= 0; --k) {
    for (int i = parent[k]; i != -1; i = parent[i]) {
      const double a = H[k * n + i] / H[k * n + k];
      for (int j = i; j != -1; j = parent[j]) H[i * n + j] -= a * H[k * n + j];
      H[k * n + i] = a;
    }
  }
}

// x ← H⁻¹ x with H factored by factorTree.
void solveTree(const double* H, int n, const std::vector<std::int32_t>& parent, double* x) {
  for (int i = n - 1; i >= 0; --i)
    for (int j = parent[i]; j != -1; j = parent[j]) x[j] -= H[i * n + j] * x[i];
  for (int i = 0; i < n; ++i) x[i] /= H[i * n + i];
  for (int i = 0; i < n; ++i)
    for (int j = parent[i]; j != -1; j = parent[j]) x[i] -= H[i * n + j] * x[j];
}

}  // namespace

int positionCountOf(BodyJointKind kind) {
  switch (kind) {
    case BodyJointKind::kWeld:
      return 0;
    case BodyJointKind::kRevolute:
    case BodyJointKind::kPrismatic:
      return 1;
    case BodyJointKind::kFree:
      return 7;
    case BodyJointKind::kBall:
      return 4;
  }
  return 0;
}

int velocityCountOf(BodyJointKind kind) {
  switch (kind) {
    case BodyJointKind::kFree:
      return 6;
    case BodyJointKind::kBall:
      return 3;
    default:
      return positionCountOf(kind);
  }
}

std::int32_t Multibody::frameIndex(const std::string& frameName) const {
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (frames[i].name == frameName) return static_cast<std::int32_t>(i);
  return -1;
}

std::int32_t Multibody::bodyIndex(const std::string& bodyName) const {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == bodyName) return static_cast<std::int32_t>(i);
  return -1;
}

void finalize(Multibody& multibody) {
  std::int32_t q = 0, v = 0;
  multibody.dofBody.clear();
  multibody.dofParent.clear();
  std::vector<std::int32_t> lastDof(multibody.bodies.size(), -1);
  for (std::size_t b = 0; b < multibody.bodies.size(); ++b) {
    MultibodyBody& body = multibody.bodies[b];
    const auto fail = [&](const std::string& what) {
      throw std::invalid_argument(describe(multibody, b) + ": " + what);
    };
    if (body.parent < -1 || body.parent >= static_cast<std::int32_t>(b))
      fail("parent " + std::to_string(body.parent) + " must be -1 or an earlier body");
    if ((body.joint == BodyJointKind::kFree || body.joint == BodyJointKind::kWeld) &&
        body.parent != -1)
      fail("a free or welded joint must have the world as parent (weld bodies are merged)");
    const BodyMassProperties& mp = body.mass;
    if (!(mp.mass > 0.0) || !std::isfinite(mp.mass))
      fail("mass must be > 0 and finite, got " + std::to_string(mp.mass));
    const Mat3& I = mp.inertia;
    const double a = I.m[0][0], bb = I.m[1][1], c = I.m[2][2];
    if (!(a >= 0 && bb >= 0 && c >= 0) || !std::isfinite(a + bb + c))
      fail("inertia diagonal must be >= 0 and finite");
    const double slack = 1e-12 * (a + bb + c);
    // Principal moments satisfy the triangle inequalities; checked on the eigen-free
    // form: each diagonal entry at most the sum of the other two (necessary), and
    // the matrix positive semi-definite by its leading minors.
    if (a > bb + c + slack || bb > a + c + slack || c > a + bb + slack)
      fail("inertia violates the triangle inequality (ixx " + std::to_string(a) + ", iyy " +
           std::to_string(bb) + ", izz " + std::to_string(c) + ")");
    if (!isRotation(body.X_PJ.rotation)) fail("X_PJ's rotation is not a rotation");
    if (body.joint == BodyJointKind::kRevolute || body.joint == BodyJointKind::kPrismatic) {
      const double n = norm(body.axis);
      if (!(std::abs(n - 1.0) < 1e-9))
        fail("axis must be a unit vector, |axis| = " + std::to_string(n));
      if (!(body.lower <= body.upper)) fail("lower limit above upper");
    }
    if (!(body.damping >= 0) || !(body.friction >= 0) || !(body.armature >= 0) ||
        !(body.effortLimit > 0))
      fail("damping, friction, armature must be >= 0 and the effort limit > 0");
    body.qStart = q;
    body.vStart = v;
    q += positionCountOf(body.joint);
    const int nv = velocityCountOf(body.joint);
    std::int32_t previous = body.parent >= 0 ? lastDof[body.parent] : -1;
    for (int k = 0; k < nv; ++k) {
      multibody.dofBody.push_back(static_cast<std::int32_t>(b));
      multibody.dofParent.push_back(previous);
      previous = v + k;
    }
    v += nv;
    lastDof[b] = previous;
  }
  for (MultibodyFrame& frame : multibody.frames)
    if (frame.body < 0 || frame.body >= static_cast<std::int32_t>(multibody.bodies.size()))
      throw std::invalid_argument("multibody '" + multibody.name + "': frame '" + frame.name +
                                  "' names body " + std::to_string(frame.body));
  multibody.positionCount = q;
  multibody.velocityCount = v;
}

std::vector<double> neutralConfiguration(const Multibody& multibody) {
  std::vector<double> q(static_cast<std::size_t>(multibody.positionCount), 0.0);
  for (const MultibodyBody& body : multibody.bodies) {
    if (velocityCountOf(body.joint) == 1) {
      q[static_cast<std::size_t>(body.qStart)] = std::clamp(0.0, body.lower, body.upper);
      continue;
    }
    if (body.joint == BodyJointKind::kBall) {
      q[static_cast<std::size_t>(body.qStart)] = 1.0;  // no turn: (1, 0, 0, 0)
      continue;
    }
    if (body.joint != BodyJointKind::kFree) continue;
    const Quaternion r = quaternionFromMatrix(body.X_PJ.rotation);
    double* x = q.data() + body.qStart;
    x[0] = body.X_PJ.translation.x;
    x[1] = body.X_PJ.translation.y;
    x[2] = body.X_PJ.translation.z;
    x[3] = r.w;
    x[4] = r.x;
    x[5] = r.y;
    x[6] = r.z;
  }
  return q;
}

void updateKinematics(const Multibody& multibody, const double* q, MultibodyKinematics& kin) {
  const std::size_t n = multibody.bodies.size();
  kin.X_WB.resize(n);
  kin.motion.resize(static_cast<std::size_t>(multibody.velocityCount));
  kin.mass.resize(n);
  kin.firstMoment.resize(n);
  kin.inertiaAtOrigin.resize(n);
  for (std::size_t b = 0; b < n; ++b) {
    const MultibodyBody& body = multibody.bodies[b];
    const Pose X_WP = body.parent >= 0 ? kin.X_WB[body.parent] : Pose{};
    const double* qb = q + body.qStart;
    SpatialVector* S = kin.motion.data() + body.vStart;
    switch (body.joint) {
      case BodyJointKind::kWeld:
        kin.X_WB[b] = X_WP * body.X_PJ;
        break;
      case BodyJointKind::kRevolute: {
        const Pose X_WJ = X_WP * body.X_PJ;
        kin.X_WB[b] = {X_WJ.rotation * rotationAboutAxis(body.axis, qb[0]), X_WJ.translation};
        const Vec3 axis_W = X_WJ.rotation * body.axis;
        S[0] = {axis_W, cross(X_WJ.translation, axis_W)};
        break;
      }
      case BodyJointKind::kPrismatic: {
        const Pose X_WJ = X_WP * body.X_PJ;
        const Vec3 axis_W = X_WJ.rotation * body.axis;
        kin.X_WB[b] = {X_WJ.rotation, X_WJ.translation + axis_W * qb[0]};
        S[0] = {{}, axis_W};
        break;
      }
      case BodyJointKind::kBall: {
        // B turned by q about J's origin; its three rates turn about J's axes,
        // which the parent carries (so the bias below is the revolute joint's).
        const Pose X_WJ = X_WP * body.X_PJ;
        kin.X_WB[b] = {X_WJ.rotation * rotationMatrix(normalized({qb[0], qb[1], qb[2], qb[3]})),
                       X_WJ.translation};
        for (int k = 0; k < 3; ++k) {
          Vec3 e{};
          (k == 0 ? e.x : (k == 1 ? e.y : e.z)) = 1.0;
          const Vec3 axis_W = X_WJ.rotation * e;
          S[k] = {axis_W, cross(X_WJ.translation, axis_W)};
        }
        break;
      }
      case BodyJointKind::kFree: {
        const Quaternion r = normalized({qb[3], qb[4], qb[5], qb[6]});
        const Vec3 p{qb[0], qb[1], qb[2]};
        kin.X_WB[b] = {rotationMatrix(r), p};
        for (int k = 0; k < 3; ++k) {
          Vec3 e{};
          (k == 0 ? e.x : (k == 1 ? e.y : e.z)) = 1.0;
          S[k] = {e, cross(p, e)};
          S[3 + k] = {{}, e};
        }
        break;
      }
    }
    const Pose& X = kin.X_WB[b];
    const double m = body.mass.mass;
    const Vec3 c = X * body.mass.centerOfMass;
    const Mat3 Ic = X.rotation * body.mass.inertia * transpose(X.rotation);
    kin.mass[b] = m;
    kin.firstMoment[b] = c * m;
    kin.inertiaAtOrigin[b] =
        Ic + m * (Mat3::diagonal({dot(c, c), dot(c, c), dot(c, c)}) - outer(c, c));
  }
}

void updateVelocities(const Multibody& multibody, const double* v, MultibodyKinematics& kin) {
  const std::size_t n = multibody.bodies.size();
  kin.velocity.resize(n);
  kin.biasAcceleration.resize(n);
  for (std::size_t b = 0; b < n; ++b) {
    const MultibodyBody& body = multibody.bodies[b];
    const SpatialVector parent = body.parent >= 0 ? kin.velocity[body.parent] : SpatialVector{};
    SpatialVector joint{};
    const int nv = velocityCountOf(body.joint);
    for (int k = 0; k < nv; ++k) joint = joint + kin.motion[body.vStart + k] * v[body.vStart + k];
    kin.velocity[b] = parent + joint;
    if (body.joint == BodyJointKind::kFree) {
      // S depends on the body origin p: d/dt (S v) at fixed v is (0, ṗ × ω).
      const double* vb = v + body.vStart;
      kin.biasAcceleration[b] = {{}, cross(Vec3{vb[3], vb[4], vb[5]}, Vec3{vb[0], vb[1], vb[2]})};
    } else {
      // A joint axis fixed in the parent: Ṡ q̇ = V_parent ×m (S q̇).
      kin.biasAcceleration[b] = crossMotion(parent, joint);
    }
  }
}

Pose framePose(const Multibody& multibody, const MultibodyKinematics& kin, std::int32_t frame) {
  const MultibodyFrame& f = multibody.frames.at(static_cast<std::size_t>(frame));
  return kin.X_WB[f.body] * f.X_BF;
}

Vec3 pointVelocity(const MultibodyKinematics& kin, std::int32_t body, const Vec3& p_WP) {
  const SpatialVector& V = kin.velocity[body];
  return V.linear + cross(V.angular, p_WP);
}

void pointJacobian(const Multibody& multibody, const MultibodyKinematics& kin, std::int32_t body,
                   const Vec3& p_WP, double* translational, double* rotational) {
  const int nv = multibody.velocityCount;
  std::fill(translational, translational + 3 * nv, 0.0);
  if (rotational) std::fill(rotational, rotational + 3 * nv, 0.0);
  for (std::int32_t b = body; b != -1; b = multibody.bodies[b].parent) {
    const MultibodyBody& mb = multibody.bodies[b];
    for (int k = 0; k < velocityCountOf(mb.joint); ++k) {
      const int column = mb.vStart + k;
      const SpatialVector& S = kin.motion[column];
      const Vec3 v = S.linear + cross(S.angular, p_WP);
      translational[column] = v.x;
      translational[nv + column] = v.y;
      translational[2 * nv + column] = v.z;
      if (rotational) {
        rotational[column] = S.angular.x;
        rotational[nv + column] = S.angular.y;
        rotational[2 * nv + column] = S.angular.z;
      }
    }
  }
}

void inverseDynamics(const Multibody& multibody, const MultibodyKinematics& kin, const double* a,
                     const Vec3& gravity, const SpatialVector* externalWrench, double* tau) {
  inverseDynamics(multibody, kin, a, gravity, externalWrench, tau, nullptr, nullptr);
}

void inverseDynamics(const Multibody& multibody, const MultibodyKinematics& kin, const double* a,
                     const Vec3& gravity, const SpatialVector* externalWrench, double* tau,
                     SpatialVector* bodyAcceleration, SpatialVector* jointWrench) {
  const std::size_t n = multibody.bodies.size();
  std::vector<SpatialVector> acceleration(n), force(n);
  for (std::size_t b = 0; b < n; ++b) {
    const MultibodyBody& body = multibody.bodies[b];
    // Gravity as the world's acceleration −g (Featherstone's fictitious base acceleration).
    SpatialVector A = body.parent >= 0 ? acceleration[body.parent] : SpatialVector{{}, -gravity};
    A = A + kin.biasAcceleration[b];
    if (a)
      for (int k = 0; k < velocityCountOf(body.joint); ++k)
        A = A + kin.motion[body.vStart + k] * a[body.vStart + k];
    acceleration[b] = A;
    const SpatialVector& V = kin.velocity[b];
    const SpatialVector IV =
        applyInertia(kin.mass[b], kin.firstMoment[b], kin.inertiaAtOrigin[b], V);
    force[b] = applyInertia(kin.mass[b], kin.firstMoment[b], kin.inertiaAtOrigin[b], A) +
               crossForce(V, IV);
    if (externalWrench) force[b] = force[b] + externalWrench[b] * -1.0;
  }
  for (std::size_t b = n; b-- > 0;) {
    const MultibodyBody& body = multibody.bodies[b];
    for (int k = 0; k < velocityCountOf(body.joint); ++k)
      tau[body.vStart + k] = dotMotionForce(kin.motion[body.vStart + k], force[b]);
    if (body.parent >= 0) force[body.parent] = force[body.parent] + force[b];
  }
  if (bodyAcceleration) std::copy(acceleration.begin(), acceleration.end(), bodyAcceleration);
  if (jointWrench) std::copy(force.begin(), force.end(), jointWrench);
}

void solveMassMatrix(const Multibody& multibody, const MultibodyKinematics& kin, double* x) {
  const int nv = multibody.velocityCount;
  const auto n = static_cast<std::size_t>(nv);
  std::vector<double> M(n * n);
  massMatrix(multibody, kin, M.data());
  for (const MultibodyBody& body : multibody.bodies)
    if (velocityCountOf(body.joint) == 1) M[body.vStart * n + body.vStart] += body.armature;
  factorTree(M.data(), nv, multibody.dofParent);
  solveTree(M.data(), nv, multibody.dofParent, x);
}

void forwardDynamics(const Multibody& multibody, const MultibodyKinematics& kin, const double* tau,
                     const Vec3& gravity, const SpatialVector* externalWrench, double* a) {
  const auto n = static_cast<std::size_t>(multibody.velocityCount);
  // a = (M + A)⁻¹ (τ − c), c the bias with the external wrenches (inverse dynamics at a = 0).
  inverseDynamics(multibody, kin, nullptr, gravity, externalWrench, a);
  for (std::size_t i = 0; i < n; ++i) a[i] = tau[i] - a[i];
  solveMassMatrix(multibody, kin, a);
}

void massMatrix(const Multibody& multibody, const MultibodyKinematics& kin, double* M) {
  const std::size_t n = multibody.bodies.size();
  const int nv = multibody.velocityCount;
  std::fill(M, M + static_cast<std::size_t>(nv) * nv, 0.0);
  std::vector<double> m(kin.mass);
  std::vector<Vec3> h(kin.firstMoment);
  std::vector<Mat3> I(kin.inertiaAtOrigin);
  for (std::size_t b = n; b-- > 0;) {
    const MultibodyBody& body = multibody.bodies[b];
    for (int k = 0; k < velocityCountOf(body.joint); ++k) {
      const int i = body.vStart + k;
      const SpatialVector F = applyInertia(m[b], h[b], I[b], kin.motion[i]);
      for (int j = i; j != -1; j = multibody.dofParent[j]) {
        const double value = dotMotionForce(kin.motion[j], F);
        M[j * nv + i] = value;
        M[i * nv + j] = value;
      }
    }
    if (body.parent >= 0) {
      m[body.parent] += m[b];
      h[body.parent] += h[b];
      I[body.parent] = I[body.parent] + I[b];
    }
  }
}

double kineticEnergy(const MultibodyKinematics& kin) {
  double energy = 0.0;
  for (std::size_t b = 0; b < kin.mass.size(); ++b) {
    const SpatialVector& V = kin.velocity[b];
    energy += 0.5 * dotMotionForce(V, applyInertia(kin.mass[b], kin.firstMoment[b],
                                                   kin.inertiaAtOrigin[b], V));
  }
  return energy;
}

double gravitationalEnergy(const MultibodyKinematics& kin, const Vec3& gravity) {
  double energy = 0.0;
  for (const Vec3& h : kin.firstMoment) energy -= dot(h, gravity);
  return energy;
}

SpatialVector spatialMomentum(const MultibodyKinematics& kin) {
  SpatialVector total{};
  for (std::size_t b = 0; b < kin.mass.size(); ++b)
    total = total +
            applyInertia(kin.mass[b], kin.firstMoment[b], kin.inertiaAtOrigin[b], kin.velocity[b]);
  return total;
}

namespace {

// The unit quaternion (w, x, y, z) at `wxyz` turned by exp(δ ω) on the left:
// R⁺ = exp(δ ω) R, ω in the frame R maps into.
void turnQuaternion(double* wxyz, const double* omega, double dt) {
  const Quaternion turned =
      normalized(quaternionFromRotationVector(Vec3{omega[0], omega[1], omega[2]} * dt) *
                 Quaternion{wxyz[0], wxyz[1], wxyz[2], wxyz[3]});
  wxyz[0] = turned.w;
  wxyz[1] = turned.x;
  wxyz[2] = turned.y;
  wxyz[3] = turned.z;
}

}  // namespace

void integrateConfiguration(const Multibody& multibody, double* q, const double* v, double dt) {
  for (const MultibodyBody& body : multibody.bodies) {
    double* qb = q + body.qStart;
    const double* vb = v + body.vStart;
    switch (body.joint) {
      case BodyJointKind::kWeld:
        break;
      case BodyJointKind::kRevolute:
      case BodyJointKind::kPrismatic:
        qb[0] += dt * vb[0];
        break;
      case BodyJointKind::kBall:
        turnQuaternion(qb, vb, dt);
        break;  // ω in J
      case BodyJointKind::kFree:
        qb[0] += dt * vb[3];
        qb[1] += dt * vb[4];
        qb[2] += dt * vb[5];
        turnQuaternion(qb + 3, vb, dt);  // the world's angular velocity
        break;
    }
  }
}

namespace {

// One row of the step's impulse problem: the rate `dof` is held to `target` with an
// impulse in [low, high] (a hard stop: one-sided; friction: ±dt F).
// A saturating servo's row is soft: its impulse λ = δ g (target − v⁺) while within
// its bounds (g = β + δ κ, the servo's implicit gain), `softness` 1/(δ g); 0 for a
// hard row.
struct ImpulseRow {
  std::int32_t dof;
  double target, low, high;
  double softness = 0.0;
};

// x = A⁻¹ b for a symmetric positive definite 3×3 A (Cholesky).
Vec3 solveSymmetric(const Mat3& A, const Vec3& b) {
  const double l00 = std::sqrt(A.m[0][0]);
  const double l10 = A.m[1][0] / l00, l20 = A.m[2][0] / l00;
  const double l11 = std::sqrt(A.m[1][1] - l10 * l10);
  const double l21 = (A.m[2][1] - l20 * l10) / l11;
  const double l22 = std::sqrt(A.m[2][2] - l20 * l20 - l21 * l21);
  const double y0 = b.x / l00, y1 = (b.y - l10 * y0) / l11, y2 = (b.z - l20 * y0 - l21 * y1) / l22;
  const double x2 = y2 / l22, x1 = (y1 - l21 * x2) / l11, x0 = (y0 - l10 * x1 - l20 * x2) / l00;
  return {x0, x1, x2};
}

// A free tree's semi-implicit step keeps its momentum only to O(dt²) a step (the
// momentum map changes with q within the step). The whole tree is given the
// rigid velocity change ΔV that restores h⁺ = h + dt W exactly: I_tot ΔV = Δh,
// every body's velocity shifted by the same ΔV, the joint rates untouched.
void restoreMomentum(const Multibody& multibody, const double* q, double* v,
                     const SpatialVector& target, MultibodyKinematics& kin) {
  updateKinematics(multibody, q, kin);
  updateVelocities(multibody, v, kin);
  const SpatialVector now = spatialMomentum(kin);
  const Vec3 dL = target.angular - now.angular, dP = target.linear - now.linear;
  double m = 0.0;
  Vec3 h{};
  Mat3 I = Mat3::zero();
  for (std::size_t b = 0; b < kin.mass.size(); ++b) {
    m += kin.mass[b];
    h += kin.firstMoment[b];
    I = I + kin.inertiaAtOrigin[b];
  }
  // (I_O ω + h × v, m v − h × ω) = (dL, dP): ω from the inertia about the centre.
  const Mat3 hx = Mat3::crossMatrix(h);
  const Mat3 aboutCentre = I + (1.0 / m) * (hx * hx);
  const Vec3 omega = solveSymmetric(aboutCentre, dL - cross(h, dP) / m);
  const Vec3 vOrigin = (dP + cross(h, omega)) / m;
  const MultibodyBody& base = multibody.bodies[0];
  const Vec3 p{q[base.qStart], q[base.qStart + 1], q[base.qStart + 2]};
  const Vec3 vBase = vOrigin + cross(omega, p);
  double* vb = v + base.vStart;
  vb[0] += omega.x;
  vb[1] += omega.y;
  vb[2] += omega.z;
  vb[3] += vBase.x;
  vb[4] += vBase.y;
  vb[5] += vBase.z;
}

// Projected Gauss–Seidel on the rows' exact Delassus matrix W = (A⁻¹)_rows (A
// factored in ws.massMatrix): velocity = v_free + A⁻¹ Σ e_r λ_r with each λ_r in
// its bounds and its row's target met where the bounds allow. Rows already solved
// keep their impulses as the starting point.
void solveImpulses(const std::vector<ImpulseRow>& rows, int nv,
                   const std::vector<std::int32_t>& parent, MultibodyWorkspace& ws,
                   std::vector<double>& velocity) {
  const auto n = static_cast<std::size_t>(nv);
  const std::size_t m = rows.size(), known = ws.impulse.size();
  ws.impulse.resize(m, 0.0);
  ws.delassus.resize(m * n);
  for (std::size_t r = known; r < m; ++r) {  // column r: A⁻¹ e_dof(r)
    double* column = ws.delassus.data() + r * n;
    std::fill(column, column + n, 0.0);
    column[rows[r].dof] = 1.0;
    solveTree(ws.massMatrix.data(), nv, parent, column);
  }
  for (int sweep = 0; sweep < 200; ++sweep) {
    double change = 0.0;
    for (std::size_t r = 0; r < m; ++r) {
      const double* column = ws.delassus.data() + r * n;
      const double w = column[rows[r].dof];
      const double old = ws.impulse[r];
      const double soft = rows[r].softness;
      const double next =
          std::clamp(old + (rows[r].target - velocity[rows[r].dof] - soft * old) / (w + soft),
                     rows[r].low, rows[r].high);
      const double delta = next - old;
      if (delta != 0.0) {
        ws.impulse[r] = next;
        for (std::size_t i = 0; i < n; ++i) velocity[i] += delta * column[i];
        change = std::max(change, std::abs(delta * w));
      }
    }
    if (change < 1e-14) break;
  }
}

double inputAt(const std::vector<double>& values, std::size_t i) {
  return values.empty() ? 0.0 : values[i];
}

// K x for a point load's K = k_n n nᵀ + k_t (I − n nᵀ) (or its C, with the dampings).
Vec3 pointLoadTimes(const Vec3& n, double normal, double tangential, const Vec3& x) {
  const Vec3 along = n * dot(n, x);
  return along * normal + (x - along) * tangential;
}

// The implicit point loads' terms: each load's Jacobian J (3 × n, into jacobians),
// their matrix Σ Jᵀ (dt C + dt² K) J (n × n, into matrix) and right-hand side
// −dt² Σ Jᵀ K J v (into rhs). Jᵀ X J is non-zero only between a body's ancestors'
// rates, within the mass matrix's tree pattern.
void assemblePointLoads(const Multibody& multibody, const MultibodyKinematics& kin,
                        const std::vector<PointLoadStiffness>& loads, const std::vector<double>& v,
                        double dt, std::vector<double>& jacobians, std::vector<double>& matrix,
                        std::vector<double>& rhs) {
  const auto n = static_cast<std::size_t>(multibody.velocityCount);
  jacobians.assign(3 * n * loads.size(), 0.0);
  matrix.assign(n * n, 0.0);
  rhs.assign(n, 0.0);
  for (std::size_t l = 0; l < loads.size(); ++l) {
    const PointLoadStiffness& load = loads[l];
    double* J = jacobians.data() + 3 * n * l;
    pointJacobian(multibody, kin, load.body, load.point, J, nullptr);
    // Columns: the Jacobian's non-zero rates (the body's ancestors' rates).
    Vec3 pointVelocity{};
    for (std::size_t i = 0; i < n; ++i) pointVelocity += Vec3{J[i], J[n + i], J[2 * n + i]} * v[i];
    const Vec3 stiffnessTimesVelocity =
        pointLoadTimes(load.normal, load.normalStiffness, load.tangentialStiffness, pointVelocity);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 column{J[i], J[n + i], J[2 * n + i]};
      if (column.x == 0.0 && column.y == 0.0 && column.z == 0.0) continue;
      rhs[i] -= dt * dt * dot(column, stiffnessTimesVelocity);
      const Vec3 weighted =
          pointLoadTimes(load.normal, dt * load.normalDamping + dt * dt * load.normalStiffness,
                         dt * load.tangentialDamping + dt * dt * load.tangentialStiffness, column);
      for (std::size_t k = 0; k < n; ++k)
        matrix[i * n + k] += dot(weighted, Vec3{J[k], J[n + k], J[2 * n + k]});
    }
  }
}

}  // namespace

MultibodyStepReport stepMultibody(const Multibody& multibody, std::vector<double>& q,
                                  std::vector<double>& v, const MultibodyInputs& inputs, double dt,
                                  const Vec3& gravity, MultibodyWorkspace& ws) {
  return stepMultibody(multibody, q, v, inputs, {}, dt, gravity, ws);
}

MultibodyStepReport stepMultibody(const Multibody& multibody, std::vector<double>& q,
                                  std::vector<double>& v, const MultibodyInputs& inputs,
                                  const std::vector<PointLoadStiffness>& implicitLoads, double dt,
                                  const Vec3& gravity, MultibodyWorkspace& ws) {
  const int nv = multibody.velocityCount;
  const auto n = static_cast<std::size_t>(nv);
  MultibodyStepReport report;
  MultibodyKinematics& kin = ws.kinematics;
  updateKinematics(multibody, q.data(), kin);
  updateVelocities(multibody, v.data(), kin);
  ws.massMatrix.resize(n * n);
  ws.rhs.resize(n);
  ws.tau.resize(n);
  ws.mass.resize(n * n);  // M(q), kept: each round below factors a copy
  massMatrix(multibody, kin, ws.mass.data());
  inverseDynamics(multibody, kin, nullptr, gravity,
                  inputs.wrench.empty() ? nullptr : inputs.wrench.data(), ws.tau.data());
  // The contacts' implicit terms (multibody_contacts.h), in buffers kept between steps.
  thread_local std::vector<double> loadJacobians, loadMatrix, loadRhs;
  const bool loaded = !implicitLoads.empty();
  if (loaded)
    assemblePointLoads(multibody, kin, implicitLoads, v, dt, loadJacobians, loadMatrix, loadRhs);

  // The implicit terms: joint damping b and the servos' κ and β on the diagonal;
  // scratch holds each rate's explicit effort. A servo whose effort at the solution
  // passes its bound leaves the matrix and becomes a soft row of the impulse problem
  // below (its effort g (v_t − v⁺), g = β + δ κ, within the bound less the explicit
  // effort), where it holds within its bound or saturates as v⁺ decides: a bounded
  // servo solved at v⁺, not saturated once from the unbounded solution (which let a
  // velocity-limited finger pressing on a ball flip between saturated and held at
  // every step, the energy error steering the step down to microseconds). A servo
  // leaves the matrix once, so the rounds end.
  ws.scratch.resize(n);
  ws.servo.resize(2 * n);                  // each rate's servo (κ, β)
  thread_local std::vector<double> bound;  // each rate's effort bound
  bound.assign(n, 0.0);
  std::vector<std::int32_t>& asRow = ws.constrained;  // 1: the rate's servo is a row
  asRow.assign(n, 0);
  for (std::size_t round = 0; round <= n; ++round) {
    ws.massMatrix = ws.mass;
    if (loaded)
      for (std::size_t k = 0; k < n * n; ++k) ws.massMatrix[k] += loadMatrix[k];
    for (std::size_t i = 0; i < n; ++i) {
      const MultibodyBody& body = multibody.bodies[multibody.dofBody[i]];
      const bool oneDof = velocityCountOf(body.joint) == 1;
      const double qi = oneDof ? q[body.qStart] : 0.0;
      const double kappa = inputAt(inputs.servoStiffness, i),
                   beta = inputAt(inputs.servoDamping, i);
      const double target = inputAt(inputs.servoTarget, i),
                   targetRate = inputAt(inputs.servoTargetRate, i);
      double effort = inputAt(inputs.effort, i);
      const double damping = oneDof ? body.damping : 0.0;
      const double limit = std::min(body.effortLimit, inputs.effortLimit.empty()
                                                          ? std::numeric_limits<double>::infinity()
                                                          : inputs.effortLimit[i]);
      bound[i] = limit;
      if (oneDof && ((kappa == 0.0 && beta == 0.0) || asRow[i] != 0))
        effort = std::clamp(effort, -limit, limit);
      ws.servo[2 * i] = kappa;
      ws.servo[2 * i + 1] = beta;
      ws.scratch[i] = effort;
      const double k = asRow[i] != 0 ? 0.0 : kappa, b = asRow[i] != 0 ? 0.0 : beta;
      ws.massMatrix[i * n + i] += (oneDof ? body.armature : 0.0) + dt * (damping + b) + dt * dt * k;
      ws.rhs[i] = dt * (effort - ws.tau[i] - k * (qi + dt * v[i] - target) -
                        b * (v[i] - targetRate) - damping * v[i]);
      if (loaded) ws.rhs[i] += loadRhs[i];
    }
    factorTree(ws.massMatrix.data(), nv, multibody.dofParent);
    solveTree(ws.massMatrix.data(), nv, multibody.dofParent, ws.rhs.data());
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      const double kappa = ws.servo[2 * i], beta = ws.servo[2 * i + 1];
      const MultibodyBody& body = multibody.bodies[multibody.dofBody[i]];
      if ((kappa == 0.0 && beta == 0.0) || asRow[i] != 0 || velocityCountOf(body.joint) != 1)
        continue;
      const double next = v[i] + ws.rhs[i];
      const double effort = ws.scratch[i] -
                            kappa * (q[body.qStart] + dt * next - inputAt(inputs.servoTarget, i)) -
                            beta * (next - inputAt(inputs.servoTargetRate, i));
      if (std::abs(effort) <= bound[i]) continue;
      asRow[i] = 1;
      changed = true;
    }
    if (!changed) break;
  }
  ws.velocityFree.resize(n);
  for (std::size_t i = 0; i < n; ++i) ws.velocityFree[i] = v[i] + ws.rhs[i];

  // Hard stops, joint friction and the saturating servos: bounded impulses on v⁺
  // (projected Gauss–Seidel on the rows' exact Delassus matrix W = (A⁻¹)_rows).
  // Stop rows are added as the impulses of the others push a joint past a stop, until
  // none does (at most one round a joint).
  std::vector<ImpulseRow> rows;
  ws.impulse.clear();
  std::vector<char> stopped(multibody.bodies.size(), 0);
  for (const MultibodyBody& body : multibody.bodies)
    if (velocityCountOf(body.joint) == 1 && body.friction > 0.0)
      rows.push_back({body.vStart, 0.0, -dt * body.friction, dt * body.friction, 0.0});
  const std::size_t firstServoRow = rows.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (asRow[i] == 0) continue;
    const MultibodyBody& body = multibody.bodies[multibody.dofBody[i]];
    const double kappa = ws.servo[2 * i], beta = ws.servo[2 * i + 1];
    const double gain = beta + dt * kappa;  // τ = gain (target − v⁺)
    const double target = (beta * inputAt(inputs.servoTargetRate, i) -
                           kappa * (q[body.qStart] - inputAt(inputs.servoTarget, i))) /
                          gain;
    rows.push_back({static_cast<std::int32_t>(i), target, dt * (-bound[i] - ws.scratch[i]),
                    dt * (bound[i] - ws.scratch[i]), 1.0 / (dt * gain)});
  }
  const std::size_t servoRowsEnd = rows.size();
  std::vector<double>& velocity = ws.column;
  velocity = ws.velocityFree;
  for (std::size_t round = 0; round <= multibody.bodies.size(); ++round) {
    const std::size_t before = rows.size();
    for (std::size_t b = 0; b < multibody.bodies.size(); ++b) {
      const MultibodyBody& body = multibody.bodies[b];
      if (velocityCountOf(body.joint) != 1 || stopped[b]) continue;
      const std::int32_t i = body.vStart;
      const double qi = q[body.qStart];
      const double predicted = qi + dt * velocity[i];
      // Held at the stop; a joint already past it (moved there by an edit) comes
      // back a fifth of the way a step, not at once (no energy made in one step).
      const auto back = [&](double gap) { return (gap >= 0.0 ? gap : 0.2 * gap) / dt; };
      if (predicted > body.upper)
        rows.push_back({i, back(body.upper - qi), -1e300, 0.0, 0.0});
      else if (predicted < body.lower)
        rows.push_back({i, back(body.lower - qi), 0.0, 1e300, 0.0});
      else
        continue;
      stopped[b] = 1;
    }
    if (rows.size() == before && round > 0) break;
    if (rows.empty()) break;
    solveImpulses(rows, nv, multibody.dofParent, ws, velocity);
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<std::size_t>(rows[r].dof);
    const double impulse = ws.impulse[r], rate = velocity[i];
    if (r < firstServoRow || r >= servoRowsEnd) {
      if (impulse != 0.0) ++report.constrainedJoints;
      report.dissipated -= impulse * rate;
      continue;
    }
    // A servo row: its impulse's work λ v⁺ against the change of its spring's
    // ½ κ e² (e = q − q*, e⁺ = e + δ v⁺). Within its bound it is the servo's
    // (the target rate's work β q̇* δ v⁺ from outside, the rest dissipated, as an
    // implicit servo's); saturated, its effort is a bounded drive's, from outside,
    // and so is the spring's change (its effort no longer follows from it).
    const double kappa = ws.servo[2 * i], beta = ws.servo[2 * i + 1];
    const double e =
        q[multibody.bodies[multibody.dofBody[i]].qStart] - inputAt(inputs.servoTarget, i);
    const double springChange = 0.5 * kappa * ((e + dt * rate) * (e + dt * rate) - e * e);
    if (impulse <= rows[r].low || impulse >= rows[r].high) {
      report.inputWork += impulse * rate + springChange;
    } else {
      const double targetWork = dt * beta * inputAt(inputs.servoTargetRate, i) * rate;
      report.inputWork += targetWork;
      report.dissipated += targetWork - impulse * rate - springChange;
    }
  }
  ws.velocityFree = velocity;

  // The momentum the step must end with (a free tree): h⁺ = h + dt W, W the
  // external wrenches and gravity at q (internal joint loads cancel).
  const bool freeTree =
      !multibody.bodies.empty() && multibody.bodies[0].joint == BodyJointKind::kFree;
  SpatialVector momentumTarget{};
  if (freeTree) {
    momentumTarget = spatialMomentum(kin);
    for (std::size_t b = 0; b < multibody.bodies.size(); ++b) {
      const Vec3 weight = gravity * kin.mass[b];
      momentumTarget =
          momentumTarget + SpatialVector{cross(kin.firstMoment[b], gravity), weight} * dt;
      if (!inputs.wrench.empty()) momentumTarget = momentumTarget + inputs.wrench[b] * dt;
    }
    // Efforts on the free joint's own rates are external too: τ = Sᵀ W gives the
    // wrench W = (τ_ω + p × τ_v, τ_v) about the world origin, p the base origin.
    const MultibodyBody& base = multibody.bodies[0];
    const double* tau = ws.scratch.data() + base.vStart;
    const Vec3 p{q[static_cast<std::size_t>(base.qStart)],
                 q[static_cast<std::size_t>(base.qStart) + 1],
                 q[static_cast<std::size_t>(base.qStart) + 2]};
    const Vec3 torque{tau[0], tau[1], tau[2]}, force{tau[3], tau[4], tau[5]};
    momentumTarget = momentumTarget + SpatialVector{torque + cross(p, force), force} * dt;
  }
  // The implicit loads' change over the step, −K dt v⁺ − C Δv at each point: the
  // scheme's loss, and (a free tree) the momentum it brings.
  for (std::size_t l = 0; l < implicitLoads.size(); ++l) {
    const PointLoadStiffness& load = implicitLoads[l];
    const double* J = loadJacobians.data() + 3 * n * l;
    Vec3 after{}, change{};
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 column{J[i], J[n + i], J[2 * n + i]};
      after += column * ws.velocityFree[i];
      change += column * (ws.velocityFree[i] - v[i]);
    }
    const Vec3 spring =
        pointLoadTimes(load.normal, load.normalStiffness, load.tangentialStiffness, after);
    const Vec3 damper =
        pointLoadTimes(load.normal, load.normalDamping, load.tangentialDamping, change);
    // The damper's work at v⁺, δ u⁺ᵀ C u⁺, less what the contact stage books by the
    // trapezoid rule, ½ δ (uᵀ C u + u⁺ᵀ C u⁺), u = J v the point's velocity.
    const Vec3 before = after - change;
    const double schemeLoss =
        0.5 * dt * dt * dot(after, spring) +
        0.5 * dt *
            (dot(after,
                 pointLoadTimes(load.normal, load.normalDamping, load.tangentialDamping, after)) -
             dot(before,
                 pointLoadTimes(load.normal, load.normalDamping, load.tangentialDamping, before)));
    report.dissipated += schemeLoss;
    report.implicitLoss += schemeLoss;
    if (freeTree) {
      const Vec3 force = -(spring * dt + damper);
      momentumTarget = momentumTarget + SpatialVector{cross(load.point, force), force} * dt;
    }
  }

  // Semi-implicit Euler's own loss: the work dt τ·v⁺ exceeds the change of ½ vᵀ M v by
  // ½ Δvᵀ M Δv (Δv = v⁺ − v), removed by the scheme.
  double loss = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double row = 0.0;
    for (std::size_t k = 0; k < n; ++k) row += ws.mass[i * n + k] * (ws.velocityFree[k] - v[k]);
    const MultibodyBody& body = multibody.bodies[multibody.dofBody[i]];
    if (body.armature != 0.0 && velocityCountOf(body.joint) == 1)  // (the rotor's ½ a Δv²)
      row += body.armature * (ws.velocityFree[i] - v[i]);
    loss += (ws.velocityFree[i] - v[i]) * row;
  }
  report.dissipated += 0.5 * loss;
  for (std::size_t i = 0; i < n; ++i) {
    const MultibodyBody& body = multibody.bodies[multibody.dofBody[i]];
    const double vi = ws.velocityFree[i];
    report.inputWork += dt * ws.scratch[i] * vi;
    if (velocityCountOf(body.joint) == 1) {
      // The implicit servo's work dt τ v⁺ = −Δ(½ κ e²) − ½ κ dt² v⁺² − β dt v⁺² + β q̇* dt v⁺.
      // (A servo row's work is booked with its impulse, above.)
      const bool implicitServo = asRow[i] == 0;
      const double kappa = implicitServo ? ws.servo[2 * i] : 0.0,
                   beta = implicitServo ? ws.servo[2 * i + 1] : 0.0;
      report.dissipated += dt * (body.damping + beta + 0.5 * dt * kappa) * vi * vi;
      if (beta > 0.0) report.inputWork += dt * beta * inputAt(inputs.servoTargetRate, i) * vi;
    }
    v[i] = vi;
  }
  integrateConfiguration(multibody, q.data(), v.data(), dt);
  if (freeTree) restoreMomentum(multibody, q.data(), v.data(), momentumTarget, kin);
  return report;
}

}  // namespace robophi
