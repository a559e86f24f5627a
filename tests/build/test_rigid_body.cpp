// Geometry → mass-fitted rigid particle bodies (build/rigid_body.h): the mass,
// centre of mass and inertia asked for, masses near equal and above the floor,
// LS that hold the body rigid, frames that compose as URDF's.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "build/rigid_body_cases.h"
#include "robophi/build/rigid_body.h"

namespace robophi::build {
namespace {

void expectPointNear(const Vec3& a, const Vec3& b, double tolerance) {
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
  expectPointNear(got.centerOfMass, want.centerOfMass, 1e-6);
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
int rigidRank(const GeneratedObject& o) {
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

// Rigid (the rank, for up to 300 particles: a dense QR) and at rest.
void expectRigid(const GeneratedObject& o) {
  if (o.size() <= 300) {
    EXPECT_EQ(rigidRank(o), 3 * static_cast<int>(o.size()) - 6);
  }
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
  for (int j = 0; j < 3; ++j) expectPointNear(f.axes[j], byAxes.axes[j], 1e-15);
  const Vec3 p{0.5, -0.25, 2.0};
  expectPointNear(f.apply(p), Vec3{1, 2, 3} + byAxes.rotate(p), 1e-15);
  expectPointNear(f.inverse().apply(f.apply(p)), p, 1e-14);
  const Frame g = Frame::fromXyzRpy({-1, 0, 0.5}, {0.1, 0.2, 0.3});
  expectPointNear(f.then(g).apply(p), f.apply(g.apply(p)), 1e-14);
  // A right-handed orthonormal frame.
  EXPECT_NEAR(dot(cross(f.axes[0], f.axes[1]), f.axes[2]), 1.0, 1e-15);
}

TEST(MassProperties, PointsAndPrincipalMoments) {
  // Two 1 kg points at ±1 on x: I = diag(0, 2, 2) about the centre.
  const MassProperties p = massProperties({{-1, 0, 0}, {1, 0, 0}}, {1.0, 1.0});
  EXPECT_DOUBLE_EQ(p.mass, 2.0);
  expectPointNear(p.centerOfMass, {0, 0, 0}, 0.0);
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
  expectPointNear(p.centerOfMass, {0.1, 0, 0}, 1e-15);
  // Turned 90° about z: the body's x is the box's y.
  EXPECT_NEAR(p.inertia.xx, 6.0 * (0.2 * 0.2 + 0.36) / 12.0, 1e-12);
  EXPECT_NEAR(p.inertia.yy, 6.0 * (0.16 + 0.36) / 12.0, 1e-12);
  // Two boxes side by side (one 0.2×0.2×0.2 block sampled): the block's values.
  ShapeSpec left = box({0.1, 0.2, 0.2}), right = box({0.1, 0.2, 0.2});
  left.frame.origin = {-0.05, 0, 0};
  right.frame.origin = {0.05, 0, 0};
  const MassProperties u = uniformMassProperties({left, right}, 1.0);
  expectPointNear(u.centerOfMass, {0, 0, 0}, 1e-12);
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
  RigidBodySpec spec;
  spec.shapes = {test::cylinder(0.05, 0.3, Frame::fromXyzRpy({0, 0, 0.15}, {0, 0, 0}))};
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
  const RigidBodySpec spec = test::iiwaLink1Like();
  const RigidBody body = makeRigidBody(spec);
  EXPECT_FALSE(body.carriers.empty());
  EXPECT_TRUE(std::any_of(body.notes.begin(), body.notes.end(), [](const std::string& n) {
    return n.find("carriers added") != std::string::npos;
  }));
  expectFitted(body, {spec.mass, spec.centerOfMass, spec.inertia});
  expectRigid(body.object);
}

TEST(RigidBody, CarriersWithinALimitReachWhatTheyCan) {
  // The R2D2 finger's placeholder: 0.05 kg with I = 1 kg·m² on each axis (a
  // radius of gyration of 4.5 m) in a 9 cm finger whose origin is its corner.
  ShapeSpec finger = box({0.09, 0.04, 0.04});
  finger.frame.origin = {0.045, 0.02, 0};
  RigidBodySpec spec;
  spec.shapes = {finger};
  spec.mass = 0.05;
  spec.inertia = {1.0, 1.0, 1.0, 0, 0, 0};
  const RigidBody unlimited = makeRigidBody(spec);
  EXPECT_TRUE(unlimited.fitted);  // with carriers metres away
  spec.maxCarrierDistance = 0.5;
  const RigidBody body = makeRigidBody(spec);
  EXPECT_FALSE(body.fitted);
  EXPECT_TRUE(std::any_of(body.notes.begin(), body.notes.end(), [](const std::string& n) {
    return n.find("inertia out of reach (carriers within 0.5 m): principal moments") !=
           std::string::npos;
  }));
  const MassProperties got = massProperties(body.object.position, body.object.mass);
  EXPECT_NEAR(got.mass, spec.mass, 1e-9 * spec.mass);
  expectPointNear(got.centerOfMass, spec.centerOfMass, 1e-6);
  for (const int c : body.carriers) {
    EXPECT_LE(norm(body.object.position[static_cast<std::size_t>(c)] - spec.centerOfMass),
              0.5 + 1e-12);
  }
  // Far beyond the finger's own inertia, short of the one asked for.
  const auto moments = principalMoments(got.inertia);
  const auto own = principalMoments(uniformMassProperties(spec.shapes, spec.mass).inertia);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(moments[k], 10.0 * own[k]);
    EXPECT_LT(moments[k], 1.0);
  }
  const double mean = spec.mass / static_cast<double>(body.object.size());
  for (const double m : body.object.mass) EXPECT_GE(m, 0.2 * mean * (1 - 1e-9));
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
    expectPointNear(body.object.position[static_cast<std::size_t>(body.required[k])],
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

// A closed box mesh [lo, hi] (12 outward triangles) appended to `mesh`.
void addBoxMesh(TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, bool top = true) {
  const auto base = static_cast<std::int32_t>(mesh.vertices.size());
  for (int k = 0; k < 8; ++k) {
    mesh.vertices.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  }
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (int f = 0; f < 12; ++f) {
    if (!top && (f == 2 || f == 3)) continue;  // the z = hi face left open
    mesh.triangles.push_back({base + faces[f][0], base + faces[f][1], base + faces[f][2]});
  }
}

// A torus about z (radii R, r), nu × nv quads: 2 nu nv triangles, closed.
TriangleMesh torusMesh(int nu, int nv, double major, double minor) {
  TriangleMesh m;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      m.vertices.push_back({(major + minor * std::cos(v)) * std::cos(u),
                            (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v)});
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::int32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

ShapeSpec meshShape(TriangleMesh mesh) {
  ShapeSpec s;
  s.kind = ShapeSpec::Kind::kMesh;
  s.mesh = std::move(mesh);
  return s;
}

TEST(RigidBodyMesh, ClosedMeshesHaveTheirSolidsProperties) {
  TriangleMesh boxMesh;
  addBoxMesh(boxMesh, {-0.1, -0.05, 0}, {0.1, 0.05, 0.4});
  const MassProperties b = uniformMassProperties({meshShape(boxMesh)}, 3.0);
  expectPointNear(b.centerOfMass, {0, 0, 0.2}, 1e-15);
  EXPECT_NEAR(b.inertia.xx, 3.0 * (0.01 + 0.16) / 12, 1e-14);
  EXPECT_NEAR(b.inertia.zz, 3.0 * (0.04 + 0.01) / 12, 1e-14);
  // The 10 000-triangle torus against the solid torus (R = 0.1, r = 0.04): the
  // polygon's area is (sin(2π/50)/(2π/50)) of the circle's, 0.26 % less.
  const MassProperties t = uniformMassProperties({meshShape(torusMesh(100, 50, 0.1, 0.04))}, 1.0);
  EXPECT_NEAR(t.inertia.zz, 0.1 * 0.1 + 0.75 * 0.04 * 0.04, 0.005 * 0.0112);
  EXPECT_NEAR(t.inertia.xx, 0.5 * 0.1 * 0.1 + 0.625 * 0.04 * 0.04, 0.005 * 0.006);
}

TEST(RigidBodyMesh, TorusOf10kTrianglesFillsAtUniformDensity) {
  RigidBodySpec spec;
  spec.shapes = {meshShape(torusMesh(100, 50, 0.1, 0.04))};
  spec.mass = 1.0;
  spec.uniformDensity = true;
  for (const int count : {30, 100, 1000}) {
    spec.particleCount = count;
    const RigidBody body = makeRigidBody(spec);
    SCOPED_TRACE(count);
    expectFitted(body, body.target);
    EXPECT_TRUE(body.carriers.empty());
    EXPECT_NEAR(static_cast<double>(body.object.size()), count, 0.25 * count);
    expectRigid(body.object);
    // Every particle inside the torus (within half a cell of its tube).
    for (const Vec3& p : body.object.position) {
      const double ring = std::hypot(p.x, p.y) - 0.1;
      EXPECT_LE(std::hypot(ring, p.z), 0.04 + 0.5 * body.spacing);
    }
  }
}

TEST(RigidBodyMesh, OpenMeshStillFillsAndSaysSo) {
  TriangleMesh closed, open;
  addBoxMesh(closed, {0, 0, 0}, {0.2, 0.1, 0.1});
  addBoxMesh(open, {0, 0, 0}, {0.2, 0.1, 0.1}, false);
  RigidBodySpec spec;
  spec.mass = 1.0;
  spec.uniformDensity = true;
  spec.particleCount = 50;
  spec.shapes = {meshShape(closed)};
  const RigidBody a = makeRigidBody(spec);
  spec.shapes = {meshShape(open)};
  const RigidBody b = makeRigidBody(spec);
  EXPECT_EQ(a.object.size(), b.object.size());
  EXPECT_TRUE(std::any_of(b.notes.begin(), b.notes.end(), [](const std::string& n) {
    return n.find("mesh not closed (4 open edges)") != std::string::npos;
  }));
  // The open box's sampled solid is the closed box's within the sampling (1 %).
  EXPECT_NEAR(b.target.inertia.xx, a.target.inertia.xx, 0.01 * a.target.inertia.xx);
  EXPECT_NEAR(b.target.inertia.zz, a.target.inertia.zz, 0.01 * a.target.inertia.zz);
  expectFitted(b, b.target);
}

TEST(RigidBodyMesh, PartsThinnerThanACellGetParticles) {
  // A 0.1 m block and, apart from it, a 2 mm sheet: at a 20 mm lattice the
  // sheet holds no cell centre, and gets a layer of particles on its surface.
  TriangleMesh mesh;
  addBoxMesh(mesh, {0, 0, 0}, {0.1, 0.1, 0.1});
  addBoxMesh(mesh, {0.15, 0.0, 0.0}, {0.25, 0.002, 0.1});
  RigidBodySpec spec;
  spec.shapes = {meshShape(mesh)};
  spec.mass = 1.0;
  spec.uniformDensity = true;
  spec.particleSize = 0.02;
  const RigidBody body = makeRigidBody(spec);
  int onSheet = 0;
  for (const Vec3& p : body.object.position) {
    onSheet += p.x > 0.14 && p.x < 0.26 && p.y > -0.003 && p.y < 0.005;
  }
  EXPECT_GE(onSheet, 20);  // about (0.1 / 0.02)² = 25 cells of sheet
  EXPECT_TRUE(std::any_of(body.notes.begin(), body.notes.end(), [](const std::string& n) {
    return n.find("thinner than a cell") != std::string::npos;
  }));
  expectFitted(body, body.target);
  expectRigid(body.object);
  // Thin shapes as primitives: a 2 mm plate gets two layers inside its thickness.
  RigidBodySpec plate;
  plate.shapes = {box({0.2, 0.2, 0.002})};
  plate.mass = 0.5;
  const RigidBody sheet = makeRigidBody(plate);
  for (const Vec3& p : sheet.object.position) EXPECT_LE(std::abs(p.z), 0.001);
  expectFitted(sheet, sheet.target);
  expectRigid(sheet.object);
}

TEST(RigidBodyMesh, AFlatMeshIsASheetOfParticles) {
  // Two triangles, no thickness: a sheet of particles on the surface, its
  // uniform inertia (a 0.2 × 0.1 m plate) within 1 % though not exactly.
  TriangleMesh sheet;
  sheet.vertices = {{0, 0, 0}, {0.2, 0, 0}, {0.2, 0.1, 0}, {0, 0.1, 0}};
  sheet.triangles = {{0, 1, 2}, {0, 2, 3}};
  RigidBodySpec spec;
  spec.shapes = {meshShape(sheet)};
  spec.mass = 1.0;
  spec.uniformDensity = true;
  const RigidBody body = makeRigidBody(spec);
  EXPECT_GE(body.object.size(), 20u);
  const MassProperties got = massProperties(body.object.position, body.object.mass);
  expectPointNear(got.centerOfMass, {0.1, 0.05, 0}, 1e-6);
  const auto a = principalMoments(got.inertia);
  const double want[3] = {0.01 / 12, 0.04 / 12, 0.05 / 12};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], want[k], 0.01 * want[k]);
  for (const double r : body.object.radius) EXPECT_GT(r, 0.0);
  // A spacing far below the shape's size is refused before anything is allocated.
  spec.particleSize = 1e-6;
  try {
    makeRigidBody(spec);
    FAIL();
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field(), "particleSize");
  }
}

TEST(RigidBody, OverlappingShapesAreFilledOnce) {
  // Two copies of one box: the union is the box.
  RigidBodySpec one, two;
  one.shapes = {box({0.2, 0.1, 0.1})};
  two.shapes = {box({0.2, 0.1, 0.1}), box({0.2, 0.1, 0.1})};
  one.particleSize = two.particleSize = 0.025;
  const RigidBody a = makeRigidBody(one), b = makeRigidBody(two);
  EXPECT_EQ(a.object.size(), b.object.size());
  EXPECT_NEAR(b.target.inertia.xx, a.target.inertia.xx, 0.01 * a.target.inertia.xx);
  expectFitted(b, b.target);
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
