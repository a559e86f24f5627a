// Rotations and poses (include/robophi/rotation.h).
#include "robophi/rotation.h"

#include <algorithm>
#include <cmath>

namespace robophi {

Quaternion quaternionFromMatrix(const Mat3& r) {
  const auto& m = r.m;
  const double trace = m[0][0] + m[1][1] + m[2][2];
  Quaternion q;
  if (trace >= m[0][0] && trace >= m[1][1] && trace >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(1.0 + trace, 0.0));
    q = {0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s};
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(1.0 + m[0][0] - m[1][1] - m[2][2], 0.0));
    q = {(m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s};
  } else if (m[1][1] >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(1.0 + m[1][1] - m[0][0] - m[2][2], 0.0));
    q = {(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s};
  } else {
    const double s = 2.0 * std::sqrt(std::max(1.0 + m[2][2] - m[0][0] - m[1][1], 0.0));
    q = {(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s};
  }
  if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};
  return normalized(q);
}

Mat3 rotationFromRollPitchYaw(const Vec3& rpy) {
  const double cr = std::cos(rpy.x), sr = std::sin(rpy.x);
  const double cp = std::cos(rpy.y), sp = std::sin(rpy.y);
  const double cy = std::cos(rpy.z), sy = std::sin(rpy.z);
  return Mat3{{{{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                {-sp, cp * sr, cp * cr}}}};
}

Mat3 rotationAboutAxis(const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  return Mat3{{{{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
                {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
                {t * x * z - s * y, t * y * z + s * x, t * z * z + c}}}};
}

Vec3 rotationVector(const Mat3& r) {
  Quaternion q = quaternionFromMatrix(r);
  const Vec3 v{q.x, q.y, q.z};
  const double s = norm(v);
  if (s < 1e-300) return {};
  const double angle = 2.0 * std::atan2(s, q.w);
  return v * (angle / s);
}

}  // namespace robophi
