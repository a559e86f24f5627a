// Geometry → mass-fitted rigid particle bodies (build/rigid_body.h): the mass,
// centre of mass and inertia asked for, masses near equal and above the floor,
// LS that hold the body rigid, frames that compose as URDF's.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "robophi/build/rigid_body.h"

namespace robophi::build {
namespace {

void expectNear(const Vec3& a, const Vec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// The mass fit's promise: mass 1e-9 relative, centre 1e-6 m, principal moments 1%
// (the tensor itself to 1e-6 of its trace), every mass >= floor × the mean.
void expectFitted(const RigidBody& body, const MassProperties& want, double floor = 0.2) {
  EXPECT_TRUE(body.fitted);
  const MassProperties got = massProperties(body.object.position, body.object.mass);
  EXPECT_NEAR(got.mass, want.mass, 1e-9 * want.mass);
  expectNear(got.centerOfMass, want.centerOfMass, 1e-6);
  const auto a = principalMoments(got.inertia), b = principalMoments(want.inertia);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 0.01 * b[k]) << "moment " << k;
  const double trace = want.inertia.xx + want.inertia.yy + want.inertia.zz;
  EXPECT_NEAR(got.inertia.xy, want.inertia.xy, 1e-6 * trace);
  EXPECT_NEAR(got.inertia.xz, want.inertia.xz, 1e-6 * trace);
  EXPECT_NEAR(got.inertia.yz, want.inertia.yz, 1e-6 * trace);
  const double mean = want.mass / static_cast<double>(body.object.size());
  for (const double m : body.object.mass) EXPECT_GE(m, floor * mean * (1.0 - 1e-9));
}

// Rank of the LS rigidity matrix: 3n − 6 means the LS alone hold the body rigid.
int rigidityRank(const GeneratedObject& o) {
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(o.linearSprings.size()),
                                               static_cast<Eigen::Index>(3 * o.size()));
  for (std::size_t r = 0; r < o.linearSprings.size(); ++r) {
    const auto& s = o.linearSprings[r];
    const Vec3 d = o.position[s.a] - o.position[s.b];
    for (int k = 0; k < 3; ++k) {
      rows(static_cast<Eigen::Index>(r), 3 * s.a + k) = d[k];
      rows(static_cast<Eigen::Index>(r), 3 * s.b + k) = -d[k];
    }
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(rows);
  qr.setThreshold(1e-9);
  return static_cast<int>(qr.rank());
}

void expectRigid(const GeneratedObject& o) {
  EXPECT_EQ(rigidityRank(o), 3 * static_cast<int>(o.size()) - 6);
  for (const auto& s : o.linearSprings) {
    EXPECT_NEAR(s.restLength, norm(o.position[s.a] - o.position[s.b]), 1e-12);
    EXPECT_GT(s.stiffness, 0.0);
    EXPECT_GT(s.damping, 0.0);
  }
}

ShapeSpec box(const Vec3& size) {
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kBox;
  s.size = size;
  return s;
}

TEST(Frame, XyzRpyIsRzRyRxAndComposes) {
  const Vec3 rpy{0.3, -0.4, 1.1};
  const Frame f = Frame::fromXyzRpy({1, 2, 3}, rpy);
  const Frame byAxes = Frame::fromAxisAngle({0, 0, 1}, rpy.z)
                           .then(Frame::fromAxisAngle({0, 1, 0}, rpy.y))
                           .then(Frame::fromAxisAngle({1, 0, 0}, rpy.x));
  for (int j = 0; j < 3; ++j) expectNear(f.axes[j], byAxes.axes[j], 1e-15);
  const Vec3 p{0.5, -0.25, 2.0};
  expectNear(f.apply(p), Vec3{1, 2, 3} + byAxes.rotate(p), 1e-15);
  expectNear(f.inverse().apply(f.apply(p)), p, 1e-14);
  const Frame g = Frame::fromXyzRpy({-1, 0, 0.5}, {0.1, 0.2, 0.3});
  expectNear(f.then(g).apply(p), f.apply(g.apply(p)), 1e-14);
  // A right-handed orthonormal frame.
  EXPECT_NEAR(dot(cross(f.axes[0], f.axes[1]), f.axes[2]), 1.0, 1e-15);
}

TEST(MassProperties, PointsAndPrincipalMoments) {
  // Two 1 kg points at ±1 on x: I = diag(0, 2, 2) about the centre.
  const MassProperties p = massProperties({{-1, 0, 0}, {1, 0, 0}}, {1.0, 1.0});
  EXPECT_DOUBLE_EQ(p.mass, 2.0);
  expectNear(p.centerOfMass, {0, 0, 0}, 0.0);
  EXPECT_DOUBLE_EQ(p.inertia.xx, 0.0);
  EXPECT_DOUBLE_EQ(p.inertia.yy, 2.0);
  const auto m = principalMoments({1.0, 2.0, 3.0, 0.5, 0.0, 0.0});
  EXPECT_NEAR(m[0], 1.5 - std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(m[1], 1.5 + std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(m[2], 3.0, 1e-12);
}

TEST(UniformMassProperties, PrimitivesExactUnionSampled) {
  ShapeSpec b = box({0.2, 0.4, 0.6});
  b.frame = Frame::fromXyzRpy({0.1, 0, 0}, {0, 0, std::numbers::pi / 2});
  const MassProperties p = uniformMassProperties({b}, 6.0);
  expectNear(p.centerOfMass, {0.1, 0, 0}, 1e-15);
  // Turned 90° about z: the body's x is the box's y.
  EXPECT_NEAR(p.inertia.xx, 6.0 * (0.2 * 0.2 + 0.36) / 12.0, 1e-12);
  EXPECT_NEAR(p.inertia.yy, 6.0 * (0.16 + 0.36) / 12.0, 1e-12);
  // Two boxes side by side (one 0.2×0.2×0.2 block sampled): the block's values.
  ShapeSpec left = box({0.1, 0.2, 0.2}), right = box({0.1, 0.2, 0.2});
  left.frame.origin = {-0.05, 0, 0};
  right.frame.origin = {0.05, 0, 0};
  const MassProperties u = uniformMassProperties({left, right}, 1.0);
  expectNear(u.centerOfMass, {0, 0, 0}, 1e-12);
  EXPECT_NEAR(u.inertia.xx, 0.08 / 12.0, 1e-9);
  EXPECT_NEAR(u.inertia.zz, 0.08 / 12.0, 1e-9);
}

TEST(RigidBody, BoxAtUniformDensityFitsExactly) {
  RigidBodySpec spec;
  spec.shapes = {box({0.3, 0.2, 0.1})};
  spec.mass = 2.0;
  spec.particleCount = 30;
  const RigidBody body = makeRigidBody(spec);
  // About 30 particles (the lattice nearest to the count).
  EXPECT_GE(body.object.size(), 20u);
  EXPECT_LE(body.object.size(), 60u);
  const MassProperties want{2.0, {}, {2.0 * 0.05 / 12, 2.0 * 0.1 / 12, 2.0 * 0.13 / 12, 0, 0, 0}};
  expectFitted(body, want);
  EXPECT_TRUE(body.carriers.empty());
  expectRigid(body.object);
}

TEST(RigidBody, CylinderAndSphereWithGivenInertia) {
  // A URDF-like link: a cylinder along z, COM off centre, inertia with products.
  ShapeSpec c;
  c.kind = ShapeSpec::Kind::kCylinder;
  c.radius = 0.05;
  c.length = 0.3;
  c.frame = Frame::fromXyzRpy({0, 0, 0.15}, {0, 0, 0});
  RigidBodySpec spec;
  spec.shapes = {c};
  spec.mass = 3.0;
  spec.centerOfMass = {0.005, -0.003, 0.16};
  spec.inertia = {0.02, 0.021, 0.003, 0.0005, -0.0002, 0.0001};
  for (const int count : {30, 100}) {
    spec.particleCount = count;
    const RigidBody body = makeRigidBody(spec);
    expectFitted(body, {spec.mass, spec.centerOfMass, spec.inertia});
    expectRigid(body.object);
    EXPECT_NEAR(static_cast<double>(body.object.size()), count, 0.5 * count);
  }
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kSphere;
  s.radius = 0.1;
  RigidBodySpec ball;
  ball.shapes = {s};
  ball.mass = 1.0;
  ball.particleCount = 60;
  const RigidBody body = makeRigidBody(ball);
  expectFitted(body, {1.0, {}, {0.004, 0.004, 0.004, 0, 0, 0}});
  expectRigid(body.object);
}

TEST(RigidBody, InertiaBeyondTheGeometryGetsCarriers) {
  // The KUKA iiwa's link_1 case: 4 kg, Ixx = 0.1 kg·m² in a shape that holds about half.
  ShapeSpec c;
  c.kind = ShapeSpec::Kind::kCylinder;
  c.radius = 0.07;
  c.length = 0.3;
  RigidBodySpec spec;
  spec.shapes = {c};
  spec.mass = 4.0;
  spec.centerOfMass = {0, -0.03, 0.0};
  spec.inertia = {0.1, 0.09, 0.02, 0, 0, 0};
  const RigidBody body = makeRigidBody(spec);
  EXPECT_FALSE(body.carriers.empty());
  EXPECT_TRUE(std::any_of(body.notes.begin(), body.notes.end(), [](const std::string& n) {
    return n.find("carriers added") != std::string::npos;
  }));
  expectFitted(body, {spec.mass, spec.centerOfMass, spec.inertia});
  expectRigid(body.object);
}

TEST(RigidBody, NoShapesGetsACluster) {
  RigidBodySpec spec;
  spec.mass = 0.5;
  spec.centerOfMass = {0.1, 0.2, 0.3};
  spec.inertia = {1e-3, 2e-3, 2.5e-3, 1e-4, 0, 0};
  const RigidBody body = makeRigidBody(spec);
  EXPECT_EQ(body.object.size(), 7u);
  expectFitted(body, {spec.mass, spec.centerOfMass, spec.inertia});
  expectRigid(body.object);
}

TEST(RigidBody, RequiredPointsAreParticlesTiedInThreeDimensions) {
  RigidBodySpec spec;
  spec.shapes = {box({0.4, 0.1, 0.1})};
  spec.mass = 1.0;
  spec.inertia = {1e-3, 1.4e-2, 1.4e-2, 0, 0, 0};
  // An axis centre and an axis point at the end, one point far outside.
  spec.requiredPoints = {{0.2, 0, 0}, {0.2, 0, 0.05}, {0.0, 0.0, 0.0}};
  const RigidBody body = makeRigidBody(spec);
  ASSERT_EQ(body.required.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    expectNear(body.object.position[static_cast<std::size_t>(body.required[k])],
               spec.requiredPoints[k], 0.0);
    int links = 0;
    for (const auto& s : body.object.linearSprings) {
      links += s.a == body.required[k] || s.b == body.required[k];
    }
    EXPECT_GE(links, 4);
  }
  expectFitted(body, {spec.mass, spec.centerOfMass, spec.inertia});
  expectRigid(body.object);
}

TEST(RigidBody, BadSpecNamesTheField) {
  RigidBodySpec spec;
  spec.mass = -1;
  try {
    makeRigidBody(spec);
    FAIL();
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "mass");
  }
  spec.mass = 1;
  spec.inertia = {1, 1, 3, 0, 0, 0};  // breaks the triangle inequality
  EXPECT_THROW(makeRigidBody(spec), SpecError);
  spec.inertia = {};
  spec.shapes = {box({0.1, -0.1, 0.1})};
  try {
    makeRigidBody(spec);
    FAIL();
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "shapes[0].size");
  }
}

}  // namespace
}  // namespace robophi::build
