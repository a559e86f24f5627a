#pragma once
// Rigid-body specs shared by the rigid-body tests (build/rigid_body.h).

#include "robophi/build/rigid_body.h"

namespace robophi::build::test {

/// A cylinder along its z (m).
inline ShapeSpec cylinder(double radius, double length, const Frame& frame = {}) {
  ShapeSpec c;
  c.kind = ShapeSpec::Kind::kCylinder;
  c.radius = radius;
  c.length = length;
  c.frame = frame;
  return c;
}

/// The KUKA iiwa's link_1 case: 4 kg with Ixx = 0.1 kg·m² in a cylinder
/// 0.07 × 0.3 m that holds about half of it (carriers needed).
inline RigidBodySpec iiwaLink1Like() {
  RigidBodySpec spec;
  spec.shapes = {cylinder(0.07, 0.3)};
  spec.mass = 4.0;
  spec.centerOfMass = {0, -0.03, 0.0};
  spec.inertia = {0.1, 0.09, 0.02, 0, 0, 0};
  return spec;
}

}  // namespace robophi::build::test
