#include "robophi/joints.h"

#include <cmath>

#include "forces/connector_forces.h"

namespace robophi {

namespace {

// Prismatic: the TS keeps origin (a), slider (c) and end (b) collinear; the
// value is the slider's distance from the origin along the origin→end line.
double prismaticValue(const TorsionSpring& s, const std::vector<Vec3>& p) {
  const Vec3 line = p[s.b] - p[s.a];
  const double length = norm(line);
  if (!(length > 0.0)) return norm(p[s.c] - p[s.a]);
  return dot(p[s.c] - p[s.a], line / length);
}

}  // namespace

double jointValue(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = model.joints[joint];
  const auto& p = state.position;
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[j.connector];
    return jointAngle(p[s.a], p[s.c], p[s.b], p[s.d]);
  }
  return prismaticValue(model.torsionSprings[j.connector], p);
}

double jointRate(const Model& model, const State& state, std::size_t joint) {
  const Joint& j = model.joints[joint];
  const auto& p = state.position;
  const auto& v = state.velocity;
  if (j.kind == JointKind::kRevolute) {
    const JointSpring& s = model.jointSprings[j.connector];
    return jointAngleRate(p[s.a], p[s.c], p[s.b], p[s.d], v[s.a], v[s.c], v[s.b], v[s.d]);
  }
  const TorsionSpring& s = model.torsionSprings[j.connector];
  const Vec3 line = p[s.b] - p[s.a];
  const double length = norm(line);
  if (!(length > 0.0)) return 0.0;
  return dot(v[s.c] - v[s.a], line / length);
}

}  // namespace robophi
