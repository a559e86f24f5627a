#pragma once
/// \file
/// Rotations and poses for rigid bodies (docs/model.md §7): a 3×3 matrix, a unit
/// quaternion and a pose X_AB (frame B's orientation and origin in frame A).

#include <array>
#include <cmath>

#include "robophi/vec3.h"

namespace robophi {

/// A 3×3 matrix, row-major: m[r][c].
struct Mat3 {
  std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

  static constexpr Mat3 identity() { return Mat3{}; }
  static constexpr Mat3 zero() { return Mat3{{{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}}; }
  /// The diagonal matrix diag(d).
  static constexpr Mat3 diagonal(const Vec3& d) {
    return Mat3{{{{d.x, 0, 0}, {0, d.y, 0}, {0, 0, d.z}}}};
  }
  /// The cross-product matrix [v]×: [v]× w = v × w.
  static constexpr Mat3 crossMatrix(const Vec3& v) {
    return Mat3{{{{0, -v.z, v.y}, {v.z, 0, -v.x}, {-v.y, v.x, 0}}}};
  }
  /// A symmetric matrix from its six entries xx yy zz xy xz yz.
  static constexpr Mat3 symmetric(double xx, double yy, double zz, double xy, double xz,
                                  double yz) {
    return Mat3{{{{xx, xy, xz}, {xy, yy, yz}, {xz, yz, zz}}}};
  }
  constexpr Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
  constexpr Vec3 row(int r) const { return {m[r][0], m[r][1], m[r][2]}; }
};

constexpr Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}

constexpr Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r = Mat3::zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}

constexpr Mat3 operator+(const Mat3& a, const Mat3& b) {
  Mat3 r = a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] += b.m[i][j];
  return r;
}

constexpr Mat3 operator-(const Mat3& a, const Mat3& b) {
  Mat3 r = a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] -= b.m[i][j];
  return r;
}

constexpr Mat3 operator*(double s, const Mat3& a) {
  Mat3 r = a;
  for (auto& row : r.m)
    for (double& x : row) x *= s;
  return r;
}

constexpr Mat3 transpose(const Mat3& a) {
  Mat3 r = a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

/// Aᵀ v without forming Aᵀ.
constexpr Vec3 transposeTimes(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[1][0] * v.y + a.m[2][0] * v.z,
          a.m[0][1] * v.x + a.m[1][1] * v.y + a.m[2][1] * v.z,
          a.m[0][2] * v.x + a.m[1][2] * v.y + a.m[2][2] * v.z};
}

/// The outer product a bᵀ.
constexpr Mat3 outer(const Vec3& a, const Vec3& b) {
  return Mat3{{{{a.x * b.x, a.x * b.y, a.x * b.z},
                {a.y * b.x, a.y * b.y, a.y * b.z},
                {a.z * b.x, a.z * b.y, a.z * b.z}}}};
}

/// A unit quaternion w + x i + y j + z k (Hamilton convention): v' = q v q*.
struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

constexpr Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
          a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

inline Quaternion normalized(const Quaternion& q) {
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

/// The rotation by angle |r| about r̂ (the exponential map of a rotation vector r, rad).
inline Quaternion quaternionFromRotationVector(const Vec3& r) {
  const double angle = norm(r);
  if (angle < 1e-8) {
    // Taylor: sin(a/2)/a = 1/2 - a²/48, cos(a/2) = 1 - a²/8.
    const double s = 0.5 - angle * angle / 48.0;
    return normalized({1.0 - angle * angle / 8.0, r.x * s, r.y * s, r.z * s});
  }
  const double s = std::sin(0.5 * angle) / angle;
  return {std::cos(0.5 * angle), r.x * s, r.y * s, r.z * s};
}

/// The rotation matrix of a unit quaternion.
constexpr Mat3 rotationMatrix(const Quaternion& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return Mat3{{{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}}};
}

/// The unit quaternion of a rotation matrix (Shepperd's method: the largest pivot).
Quaternion quaternionFromMatrix(const Mat3& r);

/// The rotation of roll, pitch, yaw (URDF's rpy: R = Rz(yaw) Ry(pitch) Rx(roll)).
Mat3 rotationFromRollPitchYaw(const Vec3& rpy);

/// The rotation by `angle` (rad) about the unit axis (Rodrigues).
Mat3 rotationAboutAxis(const Vec3& axis, double angle);

/// The rotation vector (axis × angle, angle in [0, π]) of a rotation matrix.
Vec3 rotationVector(const Mat3& r);

/// A pose X_AB: frame B's orientation (columns: B's axes in A) and origin in frame A.
struct Pose {
  Mat3 rotation{};
  Vec3 translation{};

  /// p_A = X_AB p_B.
  constexpr Vec3 operator*(const Vec3& p_B) const { return rotation * p_B + translation; }
};

/// X_AC = X_AB X_BC.
constexpr Pose operator*(const Pose& a, const Pose& b) {
  return {a.rotation * b.rotation, a.rotation * b.translation + a.translation};
}

/// X_BA from X_AB.
constexpr Pose inverse(const Pose& a) {
  const Mat3 rt = transpose(a.rotation);
  return {rt, -(rt * a.translation)};
}

}  // namespace robophi
