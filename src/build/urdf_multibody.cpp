// A URDF robot as rigid bodies (include/robophi/build/urdf_multibody.h): the exact
// mass properties of its links, fixed joints merged, moving joints as the joints
// of a tree in reduced coordinates.
#include "robophi/build/urdf_multibody.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <tuple>

#include "build/checks.h"
#include "build/mass_sum.h"
#include "build/shape_fill.h"
#include "build/urdf_multibody_description.h"
#include "build/urdf_parse.h"
#include "build/urdf_visuals.h"
#include "robophi/build/model_builder.h"
#include "robophi/build/rigid_body.h"
#include "robophi/build/spec_error.h"
#include "robophi/build/urdf.h"

namespace robophi::build {

namespace {

Pose poseOf(const urdf::Origin& origin) {
  return {rotationFromRollPitchYaw(origin.rpy), origin.xyz};
}

std::string where(const urdf::Description& d, const urdf::Link& link) {
  return "link '" + link.name + "' (" + d.file + ":" + std::to_string(link.line) + ")";
}

Eigen::Matrix3d toEigen(const Mat3& m) {
  Eigen::Matrix3d e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e(r, c) = m.m[r][c];
  return e;
}

Mat3 fromEigen(const Eigen::Matrix3d& e) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.m[r][c] = e(r, c);
  return m;
}

// The mass properties of a solid shape of mass m (uniform density) about its
// centre in its own frame; a mesh is taken as its bounding box (reported).
Mat3 shapeInertia(const urdf::Geometry& g, double m) {
  switch (g.kind) {
    case urdf::Geometry::Kind::kBox: {
      const Vec3 s = g.size;
      return Mat3::diagonal(Vec3{s.y * s.y + s.z * s.z, s.x * s.x + s.z * s.z, s.x * s.x + s.y * s.y} *
                            (m / 12.0));
    }
    case urdf::Geometry::Kind::kCylinder: {
      const double r = g.radius, l = g.length;
      const double side = m * (3 * r * r + l * l) / 12.0;
      return Mat3::diagonal({side, side, 0.5 * m * r * r});
    }
    case urdf::Geometry::Kind::kSphere: {
      const double i = 0.4 * m * g.radius * g.radius;
      return Mat3::diagonal({i, i, i});
    }
    case urdf::Geometry::Kind::kMesh: break;
  }
  return Mat3::zero();
}

double shapeVolume(const urdf::Geometry& g) {
  switch (g.kind) {
    case urdf::Geometry::Kind::kBox: return g.size.x * g.size.y * g.size.z;
    case urdf::Geometry::Kind::kCylinder: return std::numbers::pi * g.radius * g.radius * g.length;
    case urdf::Geometry::Kind::kSphere: return 4.0 / 3.0 * std::numbers::pi * std::pow(g.radius, 3);
    case urdf::Geometry::Kind::kMesh: return 0.0;
  }
  return 0.0;
}

// The largest mass (kg) and inertia entry (kg·m²) of a rigid link.
constexpr double kMaxRigidBodyMass = 1e12;

// A link's mass properties in its own frame, as the file gives them or from its
// geometry; balanced if asked.
BodyMassProperties linkMass(const urdf::Description& d, const urdf::Link& link,
                            const UrdfMultibodySpec& spec, std::vector<std::string>& adjustments) {
  BodyMassProperties p;
  if (!link.inertial.present || link.inertial.mass <= 0.0) return p;
  const double m = link.inertial.mass;
  // The step squares energies and stiffnesses made of masses and inertias: past
  // kMaxRigidBodyMass they overflow (docs/scene-format.md#limits).
  const auto& entries = link.inertial.inertia;
  const double largest = std::max({std::abs(entries[0]), std::abs(entries[1]), std::abs(entries[2]),
                                   std::abs(entries[3]), std::abs(entries[4]), std::abs(entries[5])});
  if (m > kMaxRigidBodyMass || largest > kMaxRigidBodyMass)
    throw UrdfError(d.file, link.inertial.line,
                    "<inertial> of link '" + link.name + "': mass " + check::number(m) +
                        " kg, largest inertia entry " + check::number(largest) +
                        " kg·m²: more than " + check::number(kMaxRigidBodyMass) +
                        " can be simulated");
  const bool fromGeometry =
      spec.inertiaFromGeometry || std::find(spec.inertiaFromGeometryLinks.begin(),
                                            spec.inertiaFromGeometryLinks.end(),
                                            link.name) != spec.inertiaFromGeometryLinks.end();
  if (fromGeometry && !link.collisions.empty()) {
    double volume = 0.0;
    for (const urdf::Collision& c : link.collisions) volume += shapeVolume(c.geometry);
    MassSum sum;
    for (const urdf::Collision& c : link.collisions) {
      const double share = volume > 0.0 ? m * shapeVolume(c.geometry) / volume
                                        : m / static_cast<double>(link.collisions.size());
      const Pose X = poseOf(c.origin);
      sum.add(share, X.translation, X.rotation * shapeInertia(c.geometry, share) * transpose(X.rotation));
    }
    p = sum.properties();
    p.mass = m;
    adjustments.push_back(where(d, link) + ": mass properties from its <collision> geometry" +
                          " (inertiaFromGeometry; meshes count as a point at their origin)");
    return p;
  }
  const auto& i = link.inertial.inertia;  // ixx iyy izz ixy ixz iyz
  const Mat3 inertial = Mat3::symmetric(i[0], i[1], i[2], i[3], i[4], i[5]);
  const Pose X = poseOf(link.inertial.origin);
  p.mass = m;
  p.centerOfMass = X.translation;
  p.inertia = X.rotation * inertial * transpose(X.rotation);
  // Physical: positive semi-definite principal moments with A + B >= C.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(toEigen(p.inertia));
  Eigen::Vector3d moments = eigen.eigenvalues();
  const double scale = std::max(1e-300, moments.cwiseAbs().maxCoeff());
  bool changed = false;
  for (int k = 0; k < 3; ++k)
    if (moments[k] < 0.0) {
      moments[k] = 0.0;
      changed = true;
    }
  for (int k = 0; k < 3; ++k) {
    const double others = moments[(k + 1) % 3] + moments[(k + 2) % 3];
    if (moments[k] > others * (1.0 + 1e-12) + 1e-15 * scale) {
      changed = true;
      // Raise the smaller of the other two so that they sum to this one.
      const int small = moments[(k + 1) % 3] < moments[(k + 2) % 3] ? (k + 1) % 3 : (k + 2) % 3;
      moments[small] += moments[k] - others;
    }
  }
  if (changed) {
    const std::string what = "principal moments (" + check::number(eigen.eigenvalues()[0]) + ", " +
                             check::number(eigen.eigenvalues()[1]) + ", " +
                             check::number(eigen.eigenvalues()[2]) + ") kg·m²";
    if (!spec.balanceInertia)
      throw UrdfError(d.file, link.inertial.line,
                      "<inertia> of link '" + link.name + "' is not physical: " + what +
                          " break the triangle inequality (balanceInertia balances them)");
    p.inertia = fromEigen(eigen.eigenvectors() * moments.asDiagonal() * eigen.eigenvectors().transpose());
    adjustments.push_back(where(d, link) + ": inertia balanced (balanceInertia): " + what + " → (" +
                          check::number(moments[0]) + ", " + check::number(moments[1]) + ", " +
                          check::number(moments[2]) + ")");
  }
  return p;
}

UrdfCollisionShape::Kind collisionKindOf(urdf::Geometry::Kind kind) {
  switch (kind) {
    case urdf::Geometry::Kind::kBox: return UrdfCollisionShape::Kind::kBox;
    case urdf::Geometry::Kind::kCylinder: return UrdfCollisionShape::Kind::kCylinder;
    case urdf::Geometry::Kind::kSphere: return UrdfCollisionShape::Kind::kSphere;
    case urdf::Geometry::Kind::kMesh: return UrdfCollisionShape::Kind::kMesh;
  }
  return UrdfCollisionShape::Kind::kBox;
}

Vec3 sizeOf(const urdf::Geometry& g) {
  switch (g.kind) {
    case urdf::Geometry::Kind::kBox: return g.size;
    case urdf::Geometry::Kind::kCylinder: return {g.radius, g.radius, g.length};
    case urdf::Geometry::Kind::kSphere: return {g.radius, g.radius, g.radius};
    case urdf::Geometry::Kind::kMesh: return {};
  }
  return {};
}

}  // namespace

UrdfMultibody makeUrdfMultibody(const UrdfMultibodySpec& spec) {
  return makeUrdfMultibody(urdf::readUrdf(spec.path, spec.packagePaths), spec);
}

UrdfMultibody makeUrdfMultibody(const urdf::Description& d, const UrdfMultibodySpec& spec) {
  UrdfMultibody out;
  out.warnings = d.warnings;
  const std::string prefix = spec.name.empty() ? d.robotName : spec.name;
  Multibody& mb = out.multibody;
  mb.name = prefix;
  out.visuals = urdfVisuals(d, prefix);
  const std::size_t linkCount = d.links.size();
  std::vector<std::int32_t> linkBody(linkCount, -1);
  std::vector<Pose> X_BL(linkCount);
  std::vector<MassSum> bodyMass;

  const urdf::Link& root = d.links[static_cast<std::size_t>(d.root)];
  MultibodyBody base;
  base.name = prefix + "." + root.name;
  base.joint = spec.fixedBase ? BodyJointKind::kWeld : BodyJointKind::kFree;
  base.jointName = spec.fixedBase ? "" : prefix + ".base";
  base.X_PJ = spec.placement;
  mb.bodies.push_back(base);
  bodyMass.emplace_back();
  linkBody[static_cast<std::size_t>(d.root)] = 0;

  for (const urdf::Joint& j : d.joints) {
    const auto p = static_cast<std::size_t>(j.parentIndex), c = static_cast<std::size_t>(j.childIndex);
    const Pose X_PJ = X_BL[p] * poseOf(j.origin);
    if (j.type == urdf::Joint::Type::kFixed) {
      linkBody[c] = linkBody[p];
      X_BL[c] = X_PJ;
      continue;
    }
    // The size budget (docs/scene-format.md#limits), as the particle importer's:
    // refused at the joint that passes it, before the tree is built.
    if (mb.bodies.size() > static_cast<std::size_t>(kMaxUrdfBodies))
      throw UrdfError(d.file, j.line,
                      "joint '" + j.name + "' makes link '" + d.links[c].name + "' moving body " +
                          std::to_string(mb.bodies.size()) + ", more than the budget of " +
                          std::to_string(kMaxUrdfBodies) +
                          " moving links of a robot (docs/scene-format.md#limits)");
    MultibodyBody body;
    body.name = prefix + "." + d.links[c].name;
    body.parent = linkBody[p];
    body.jointName = prefix + "." + j.name;
    body.joint = j.type == urdf::Joint::Type::kPrismatic ? BodyJointKind::kPrismatic
                                                         : BodyJointKind::kRevolute;
    body.X_PJ = X_PJ;
    body.axis = j.axis / norm(j.axis);
    if (j.hasLimit && j.type != urdf::Joint::Type::kContinuous) {
      body.lower = j.lower;
      body.upper = j.upper;
    }
    if (j.hasLimit && j.effort > 0.0) body.effortLimit = j.effort;
    body.damping = j.damping;
    body.friction = j.friction;
    linkBody[c] = static_cast<std::int32_t>(mb.bodies.size());
    X_BL[c] = Pose{};
    mb.bodies.push_back(body);
    bodyMass.emplace_back();
    UrdfMultibodyJoint joint;
    joint.urdfName = j.name;
    joint.name = body.jointName;
    joint.type = j.typeName;
    joint.body = linkBody[c];
    joint.line = j.line;
    if (j.hasLimit && j.velocity > 0.0) joint.velocityLimit = j.velocity;
    if (j.hasMimic) {
      joint.mimicJoint = j.mimicJoint;
      joint.multiplier = j.multiplier;
      joint.offset = j.offset;
    }
    out.joints.push_back(joint);
  }

  for (std::size_t l = 0; l < linkCount; ++l) {
    const urdf::Link& link = d.links[l];
    const auto b = static_cast<std::size_t>(linkBody[l]);
    mb.frames.push_back({prefix + "." + link.name, linkBody[l], X_BL[l]});
    const BodyMassProperties p = linkMass(d, link, spec, out.adjustments);
    if (p.mass > 0.0)
      bodyMass[b].add(p.mass, X_BL[l] * p.centerOfMass,
                      X_BL[l].rotation * p.inertia * transpose(X_BL[l].rotation));
    if (b != 0 || l != static_cast<std::size_t>(d.root)) {
      if (mb.bodies[b].name != prefix + "." + link.name && p.mass > 0.0)
        out.adjustments.push_back(where(d, link) + ": merged into body '" + mb.bodies[b].name +
                                  "' (fixed joint)");
    }
    for (const urdf::Collision& c : link.collisions) {
      UrdfCollisionShape shape;
      shape.kind = collisionKindOf(c.geometry.kind);
      shape.body = linkBody[l];
      shape.link = link.name;
      shape.X_BS = X_BL[l] * poseOf(c.origin);
      shape.size = sizeOf(c.geometry);
      shape.mesh = c.geometry.mesh;
      shape.scale = c.geometry.scale;
      shape.line = c.line;
      out.collisions.push_back(shape);
    }
  }

  for (std::size_t b = 0; b < mb.bodies.size(); ++b) {
    MultibodyBody& body = mb.bodies[b];
    body.mass = bodyMass[b].properties();
    const bool moving = body.joint != BodyJointKind::kWeld;
    const double trace = body.mass.inertia.m[0][0] + body.mass.inertia.m[1][1] + body.mass.inertia.m[2][2];
    if (body.mass.mass <= 0.0 || (moving && !(trace > 0.0))) {
      // A body without mass (a welded base: any; a moving body: the notional minimum,
      // a small sphere of 1 cm radius, so that its joint has inertia).
      const double m = body.mass.mass > 0.0 ? body.mass.mass : spec.minimumMass;
      const double i = 0.4 * m * 1e-4;
      body.mass.mass = m;
      body.mass.inertia = body.mass.inertia + Mat3::diagonal({i, i, i});
      if (moving)
        out.adjustments.push_back("body '" + body.name + "': " +
                                  (bodyMass[b].mass > 0.0 ? "point mass given the inertia of a 1 cm sphere"
                                                          : "no mass: given " + check::number(m) +
                                                                " kg as a 1 cm sphere (minimumMass)"));
    }
  }
  try {
    finalize(mb);
  } catch (const std::invalid_argument& error) {
    throw UrdfError(d.file, 0, error.what());
  }
  for (UrdfMultibodyJoint& joint : out.joints) {
    joint.positionIndex = mb.bodies[static_cast<std::size_t>(joint.body)].qStart;
    joint.velocityIndex = mb.bodies[static_cast<std::size_t>(joint.body)].vStart;
    const MultibodyBody& moved = mb.bodies[static_cast<std::size_t>(joint.body)];
    if (moved.lower > 0.0 || moved.upper < 0.0)
      out.adjustments.push_back("joint '" + joint.urdfName + "' (" + d.file + ":" + std::to_string(joint.line) +
                                "): q = 0 is outside its limits [" + check::number(moved.lower) + ", " +
                                check::number(moved.upper) + "]; it starts at " +
                                check::number(std::clamp(0.0, moved.lower, moved.upper)));
    if (!joint.mimicJoint.empty())
      out.adjustments.push_back("joint '" + joint.urdfName + "': <mimic> of '" + joint.mimicJoint +
                                "' kept as data (multiplier " + check::number(joint.multiplier) +
                                ", offset " + check::number(joint.offset) +
                                "): the joint moves on its own unless a controller couples it");
  }
  return out;
}

namespace {

Frame frameOf(const Pose& X) {
  Frame f;
  f.origin = X.translation;
  for (int c = 0; c < 3; ++c) f.axes[static_cast<std::size_t>(c)] = X.rotation.column(c);
  return f;
}

// A <collision> element as a shape in its body's frame; a mesh's vertices are not
// read here (placeUrdfMultibody reads each file once).
ShapeSpec shapeOf(const UrdfCollisionShape& c) {
  ShapeSpec shape;
  shape.frame = frameOf(c.X_BS);
  switch (c.kind) {
    case UrdfCollisionShape::Kind::kBox:
      shape.kind = ShapeSpec::Kind::kBox;
      shape.size = c.size;
      break;
    case UrdfCollisionShape::Kind::kCylinder:
      shape.kind = ShapeSpec::Kind::kCylinder;
      shape.radius = c.size.x;
      shape.length = c.size.z;
      break;
    case UrdfCollisionShape::Kind::kSphere:
      shape.kind = ShapeSpec::Kind::kSphere;
      shape.radius = c.size.x;
      break;
    case UrdfCollisionShape::Kind::kMesh:
      shape.kind = ShapeSpec::Kind::kMesh;
      break;
  }
  return shape;
}

// Particles of radius r whose outer surfaces reach a primitive's surface from
// inside (their centres r within it), r = min(spacing, half the smallest extent):
// on a flat face a grid r apart, on a curved one rings r/2 apart along the
// curve, so that the surface they make departs from the shape by at most
// r (1 − cos(asin(1/4))) ≈ 0.03 r (a wheel rolls on its true radius). Points in
// the body frame.
// The surface particles of a primitive shape (a box, a cylinder, a sphere) of
// body `body`, refused past the budget of an object before they are made.
void surfaceParticles(const ShapeSpec& shape, double spacing, const std::string& body,
                      std::vector<Vec3>& local, std::vector<double>& radius) {
  std::vector<Vec3> points;  // in the shape's frame
  // The budget (docs/scene-format.md#limits), counted before the points are made:
  // a disc of 803 m radius and 0.2 m thickness is 4e8 particles of 0.1 m (a fuzz
  // finding: 14 GB, then a hang).
  const auto budget = [&](double count, double particleRadius) {
    if (count <= static_cast<double>(kMaxParticlesPerObject)) return;
    throw SpecError("UrdfMultibodyPlacement", "particleSize",
                    "the collision shape of body '" + body + "' would make about " +
                        check::number(std::round(count)) + " surface particles of radius " +
                        check::number(particleRadius) + " m, more than the budget of " +
                        std::to_string(kMaxParticlesPerObject) +
                        " particles of an object (docs/scene-format.md#limits)");
  };
  const auto steps = [](double length, double step) {
    return std::max(1, static_cast<int>(std::ceil(length / step - 1e-9)) + 1);
  };
  const auto along = [](double half, int k, int count) {
    return count == 1 ? 0.0 : -half + 2.0 * half * k / (count - 1);
  };
  double r = 0.0;
  switch (shape.kind) {
    case ShapeSpec::Kind::kBox: {
      const Vec3 h = shape.size * 0.5;
      r = std::min({spacing, h.x, h.y, h.z});
      const Vec3 in{h.x - r, h.y - r, h.z - r};
      const double cx = 2 * in.x / r + 2, cy = 2 * in.y / r + 2, cz = 2 * in.z / r + 2;
      budget(2.0 * (cx * cy + cy * cz + cz * cx), r);
      const int nx = steps(2 * in.x, r), ny = steps(2 * in.y, r), nz = steps(2 * in.z, r);
      for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
          for (int k = 0; k < nz; ++k)
            if (i == 0 || i == nx - 1 || j == 0 || j == ny - 1 || k == 0 || k == nz - 1)
              points.push_back({along(in.x, i, nx), along(in.y, j, ny), along(in.z, k, nz)});
      break;
    }
    case ShapeSpec::Kind::kCylinder: {
      r = std::min({spacing, shape.radius, 0.5 * shape.length});
      const double rim = shape.radius - r, halfLength = 0.5 * shape.length - r;
      // The side's rings, and the two ends' discs (rings r apart, 4π m points the m-th).
      const double perRing = std::max(6.0, 4.0 * std::numbers::pi * rim / r + 1.0);
      const double discs = rim / r + 1.0;
      budget((2 * halfLength / r + 2) * perRing +
                 2.0 * (2.0 * std::numbers::pi * discs * discs + 6.0 * discs),
             r);
      const int rings = steps(2 * halfLength, r);
      for (int k = 0; k < rings; ++k) {
        const double z = along(halfLength, k, rings);
        // The round side at every ring; the flat ends as discs of rings r apart.
        const bool end = k == 0 || k == rings - 1;
        for (double radial = rim; radial > -1e-12; radial -= end ? r : 2.0 * rim + 1.0) {
          const int count = radial < 1e-9 ? 1 : std::max(6, static_cast<int>(std::ceil(2 * std::numbers::pi * radial / (0.5 * r))));
          for (int c = 0; c < count; ++c) {
            const double a = 2 * std::numbers::pi * c / count;
            points.push_back({radial * std::cos(a), radial * std::sin(a), z});
          }
        }
      }
      break;
    }
    case ShapeSpec::Kind::kSphere: {
      r = std::min(spacing, shape.radius);
      const double inner = shape.radius - r;
      budget(4 * std::numbers::pi * inner * inner / (0.25 * r * r), r);
      const int count = inner < 1e-9 ? 1 : std::max(12, static_cast<int>(std::ceil(4 * std::numbers::pi * inner * inner / (0.25 * r * r))));
      // A Fibonacci sphere: evenly spread directions.
      for (int c = 0; c < count; ++c) {
        const double z = count == 1 ? 0.0 : 1.0 - 2.0 * (c + 0.5) / count;
        const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double a = c * std::numbers::pi * (3.0 - std::sqrt(5.0));
        points.push_back(Vec3{ring * std::cos(a), ring * std::sin(a), z} * inner);
      }
      break;
    }
    case ShapeSpec::Kind::kMesh: break;
  }
  for (const Vec3& p : points) {
    local.push_back(shape.frame.apply(p));
    radius.push_back(r);
  }
}

// docs/contact.md "Round wheels": a body turned by a revolute or continuous joint
// whose one <collision> is a cylinder coaxial with that joint meets the environment
// as the cylinder (RimRing::isCylinder), so that it rolls on its true radius, not on
// the polygon of its surface particles. Two particles on the cylinder's axis, inside
// it, are appended to `local` as the ring's hub and axis points; the ring covers the
// body's particles (their mass centre, equal shares, lies on the axis). Returns no
// ring for any other body.
std::optional<RimRing> roundWheelOf(const UrdfMultibody& robot, std::size_t body,
                                    const std::vector<ShapeSpec>& shapes, std::vector<Vec3>& local,
                                    std::vector<double>& radius) {
  if (shapes.size() != 1 || shapes[0].kind != ShapeSpec::Kind::kCylinder || local.empty())
    return std::nullopt;
  const bool turning = std::any_of(robot.joints.begin(), robot.joints.end(), [&](const auto& j) {
    return j.body == static_cast<std::int32_t>(body) && (j.type == "continuous" || j.type == "revolute");
  });
  if (!turning) return std::nullopt;
  const ShapeSpec& cylinder = shapes[0];
  // Coaxial with its joint's line (body frame, through its origin).
  if (roundAbout(cylinder, {}, robot.multibody.bodies[body].axis) != RoundAbout::kCylinder)
    return std::nullopt;
  const Vec3 center = cylinder.frame.origin;
  const Vec3 along = cylinder.frame.rotate({0.0, 0.0, 1.0});
  const double tube = radius.front();
  const double inside = std::max(0.0, 0.5 * cylinder.length - tube);
  RimRing wheel;
  wheel.first = 0;
  wheel.hub = static_cast<ParticleIndex>(local.size());
  wheel.axisParticle = wheel.hub + 1;
  local.push_back(center - along * inside);
  local.push_back(center + along * std::max(inside, 1e-3 * cylinder.radius));
  radius.push_back(tube);
  radius.push_back(tube);
  wheel.count = static_cast<std::int32_t>(local.size());
  wheel.sphereRadius = cylinder.radius;
  wheel.halfLength = 0.5 * cylinder.length;
  wheel.axialOffset = inside;  // the hub to the cylinder's centre
  return wheel;
}

}  // namespace

int wheelCount(const UrdfMultibody& robot) {
  int wheels = 0;
  for (const UrdfMultibodyJoint& joint : robot.joints) {
    if (joint.type != "continuous") continue;
    const Vec3 axis = robot.multibody.bodies[static_cast<std::size_t>(joint.body)].axis;
    wheels += std::any_of(robot.collisions.begin(), robot.collisions.end(),
                          [&](const UrdfCollisionShape& c) {
                            return c.body == joint.body && roundAbout(shapeOf(c), {}, axis) != RoundAbout::kNone;
                          })
                  ? 1
                  : 0;
  }
  return wheels;
}

PlacedUrdfMultibody placeUrdfMultibody(ModelBuilder& builder, const UrdfMultibody& robot,
                                       const UrdfMultibodyPlacement& placement) {
  const Multibody& mb = robot.multibody;
  if (!(placement.particleSize >= 0.0) || placement.particlesPerBody < 1)
    throw SpecError("UrdfMultibodyPlacement", "particleSize", "particleSize must be >= 0 m and particlesPerBody >= 1, got " +
                    check::number(placement.particleSize) + " and " +
                    std::to_string(placement.particlesPerBody));
  PlacedUrdfMultibody placed;
  // Each body's collision shapes, meshes read once per file and scale.
  std::map<std::tuple<std::string, double, double, double>, TriangleMesh> meshes;
  std::vector<std::vector<ShapeSpec>> shapes(mb.bodies.size());
  for (const UrdfCollisionShape& c : robot.collisions) {
    ShapeSpec shape = shapeOf(c);
    if (c.kind == UrdfCollisionShape::Kind::kMesh) {
      const auto key = std::make_tuple(c.mesh, c.scale.x, c.scale.y, c.scale.z);
      auto found = meshes.find(key);
      if (found == meshes.end()) {
        try {
          found = meshes.emplace(key, loadMesh(c.mesh, c.scale)).first;
        } catch (const std::exception& error) {
          throw UrdfError(c.mesh, 0, std::string("<collision> mesh of link '") + c.link + "': " + error.what());
        }
        ++placed.meshesRead;
      }
      shape.mesh = found->second;
    }
    shapes[static_cast<std::size_t>(c.body)].push_back(std::move(shape));
  }
  // The bodies' poses as the robot starts.
  std::vector<double> q = placement.q.empty() ? neutralConfiguration(mb) : placement.q;
  MultibodyKinematics kin;
  if (q.size() != static_cast<std::size_t>(mb.positionCount))
    throw SpecError("UrdfMultibodyPlacement", "q", std::to_string(q.size()) + " coordinates for '" + mb.name +
                    "', which has " + std::to_string(mb.positionCount));
  updateKinematics(mb, q.data(), kin);
  RigidTree tree;
  tree.multibody = mb;
  placed.objectOfBody.assign(mb.bodies.size(), -1);
  std::vector<std::int32_t> objects;
  for (std::size_t b = 0; b < mb.bodies.size(); ++b) {
    if (shapes[b].empty()) continue;  // no <collision>: touches nothing
    const double spacing = placement.particleSize > 0.0
                               ? placement.particleSize
                               : detail::spacingFor(shapes[b], placement.particlesPerBody);
    std::vector<Vec3> local;
    std::vector<double> radius;
    for (const ShapeSpec& shape : shapes[b]) {
      if (shape.kind != ShapeSpec::Kind::kMesh) {
        surfaceParticles(shape, spacing, mb.bodies[b].name, local, radius);
        continue;
      }
      const detail::ShapeLattice lattice = detail::fillShape(shape, spacing);
      const double r = 0.5 * std::min({lattice.cell.x, lattice.cell.y, lattice.cell.z});
      for (const Vec3& p : lattice.position) {
        local.push_back(p);
        radius.push_back(r);
      }
    }
    if (local.empty()) continue;
    const std::optional<RimRing> wheel = roundWheelOf(robot, b, shapes[b], local, radius);
    ObjectPlacement object;
    object.name = mb.bodies[b].name;
    object.kind = "link";
    object.material = placement.material;
    object.geometry.rigid = true;
    object.geometry.spacing = spacing;
    const double share = mb.bodies[b].mass.mass / static_cast<double>(local.size());
    for (std::size_t k = 0; k < local.size(); ++k) {
      object.geometry.position.push_back(kin.X_WB[b] * local[k]);
      object.geometry.mass.push_back(share);
      object.geometry.radius.push_back(radius[k]);
      object.geometry.fixed.push_back(true);
    }
    if (wheel) object.geometry.rims.push_back(*wheel);
    const PlacedObject at = builder.addObject(object);
    placed.objectOfBody[b] = at.object;
    objects.push_back(at.object);
    for (std::size_t k = 0; k < local.size(); ++k)
      tree.particles.push_back({at.firstParticle + static_cast<ParticleIndex>(k), static_cast<std::int32_t>(b),
                                local[k]});
  }
  // Contacts between the robot's own bodies: none (one contact group: linear in
  // the bodies, where every pair was their square), or none across a joint.
  if (!placement.selfCollision) {
    if (objects.size() > 1) builder.excludeContactWithin(objects);
  } else {
    for (std::size_t j = 0; j < mb.bodies.size(); ++j) {
      const std::int32_t parent = mb.bodies[j].parent;
      if (parent < 0) continue;
      const std::int32_t a = placed.objectOfBody[static_cast<std::size_t>(parent)],
                         b = placed.objectOfBody[j];
      if (a >= 0 && b >= 0) builder.excludeContact(a, b);
    }
  }
  placed.tree = builder.addRigidTree(std::move(tree), q, placement.v);
  placeUrdfMultibodyVisuals(builder, robot, placed.tree, kin);
  return placed;
}

}  // namespace robophi::build
