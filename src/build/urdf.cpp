// The URDF importer: links → rigid particle bodies (makeRigidBody), joints → the
// paper's connectors (MODEL §1.3, §1.4), one placed object per link.
// docs/robots.md "Importing a URDF" says what is built and why.
#include "robophi/build/urdf.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>

#include "build/checks.h"
#include "build/urdf_parse.h"
#include "build/urdf_visuals.h"
#include "robophi/connector_forces.h"
#include "robophi/joints.h"

namespace robophi::build {

namespace {

constexpr const char* kUrdfSpec = "UrdfSpec";
using urdf::Description;
using UJoint = urdf::Joint;

Frame originFrame(const urdf::Origin& o) { return Frame::fromXyzRpy(o.xyz, o.rpy); }

Frame translation(const Vec3& t) {
  Frame f;
  f.origin = t;
  return f;
}

// A unit vector normal to n.
Vec3 normalTo(const Vec3& n) {
  const Vec3 trial = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = cross(n, trial);
  return u / norm(u);
}

UrdfJointType typeOf(UJoint::Type t) {
  switch (t) {
    case UJoint::Type::kRevolute:
      return UrdfJointType::kRevolute;
    case UJoint::Type::kContinuous:
      return UrdfJointType::kContinuous;
    case UJoint::Type::kPrismatic:
      return UrdfJointType::kPrismatic;
    case UJoint::Type::kFixed:
      break;
  }
  return UrdfJointType::kFixed;
}

// The link's <inertial> in the link frame.
MassProperties declaredOf(const urdf::Link& link) {
  MassProperties p;
  if (!link.inertial.present) return p;
  const urdf::Inertial& in = link.inertial;
  p.mass = in.mass;
  p.centerOfMass = in.origin.xyz;
  const Inertia local{in.inertia[0], in.inertia[1], in.inertia[2],
                      in.inertia[3], in.inertia[4], in.inertia[5]};
  // I_link = R I_in Rᵀ (R: the inertial frame's axes in the link frame).
  p.inertia = rotateInertia(local, Frame::fromXyzRpy({}, in.origin.rpy).inverse());
  return p;
}

MassProperties toWorld(const MassProperties& p, const Frame& frame) {
  return {p.mass, frame.apply(p.centerOfMass), rotateInertia(p.inertia, frame.inverse())};
}

ShapeSpec shapeOf(const urdf::Collision& c, const std::string& file) {
  ShapeSpec s;
  s.frame = originFrame(c.origin);
  const urdf::Geometry& g = c.geometry;
  switch (g.kind) {
    case urdf::Geometry::Kind::kBox:
      s.kind = ShapeSpec::Kind::kBox;
      s.size = g.size;
      break;
    case urdf::Geometry::Kind::kCylinder:
      s.kind = ShapeSpec::Kind::kCylinder;
      s.radius = g.radius;
      s.length = g.length;
      break;
    case urdf::Geometry::Kind::kSphere:
      s.kind = ShapeSpec::Kind::kSphere;
      s.radius = g.radius;
      break;
    case urdf::Geometry::Kind::kMesh:
      s.kind = ShapeSpec::Kind::kMesh;
      try {
        s.mesh = loadMesh(g.mesh, g.scale);
      } catch (const std::exception& error) {
        throw UrdfError(file, c.line, std::string("<collision> mesh: ") + error.what());
      }
      break;
  }
  return s;
}

// The corners of a shape's bounding box in the body frame (for sizes).
void extend(const ShapeSpec& s, Vec3& low, Vec3& high) {
  std::vector<Vec3> points;
  if (s.kind == ShapeSpec::Kind::kMesh) {
    points = s.mesh.vertices;
  } else {
    Vec3 half = s.size * 0.5;
    if (s.kind == ShapeSpec::Kind::kCylinder) half = {s.radius, s.radius, 0.5 * s.length};
    if (s.kind == ShapeSpec::Kind::kSphere) half = {s.radius, s.radius, s.radius};
    for (int k = 0; k < 8; ++k)
      points.push_back(
          {k & 1 ? half.x : -half.x, k & 2 ? half.y : -half.y, k & 4 ? half.z : -half.z});
  }
  for (const Vec3& p : points) {
    const Vec3 q = s.frame.apply(p);
    low = {std::min(low.x, q.x), std::min(low.y, q.y), std::min(low.z, q.z)};
    high = {std::max(high.x, q.x), std::max(high.y, q.y), std::max(high.z, q.z)};
  }
}

// One link with particles, while it is being assembled.
struct Body {
  int link = -1;
  Frame frame{};  // body frame = the link frame, world
  RigidBodySpec spec{};
  double spacing = 0.0;  // estimated lattice spacing (m)
  double size = 0.0;     // bounding-box diagonal (m)
  RigidBody built{};
  std::vector<Vec3> world{};              // particle positions, world
  double stiffness = 0.0, damping = 0.0;  // its LS's (N/m, N·s/m)
  // Adds a required point given in the world; returns its index in requiredPoints.
  int require(const Vec3& worldPoint) {
    spec.requiredPoints.push_back(frame.inverse().apply(worldPoint));
    return static_cast<int>(spec.requiredPoints.size()) - 1;
  }
};

// `count` particles of `body` nearest `point` (world), not all collinear when possible.
std::vector<int> nearest(const Body& body, const Vec3& point, std::size_t count,
                         const std::vector<int>& skip = {}) {
  std::vector<int> order;
  // Not the point itself (an LS needs a rest length > 0).
  for (int i = 0; i < static_cast<int>(body.world.size()); ++i)
    if (std::find(skip.begin(), skip.end(), i) == skip.end() &&
        norm(body.world[static_cast<std::size_t>(i)] - point) > 1e-6)
      order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return norm(body.world[a] - point) < norm(body.world[b] - point);
  });
  if (order.size() <= count) return order;
  std::vector<int> out(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count));
  // Replace the last pick until the set spans a plane (3 non-collinear points).
  const auto spansPlane = [&](const std::vector<int>& set) {
    for (std::size_t i = 2; i < set.size(); ++i) {
      const Vec3 u = body.world[set[1]] - body.world[set[0]];
      const Vec3 v = body.world[set[i]] - body.world[set[0]];
      if (norm(cross(u, v)) > 1e-6 * (dot(u, u) + dot(v, v))) return true;
    }
    return false;
  };
  for (std::size_t k = count; k < order.size() && count >= 3 && !spansPlane(out); ++k)
    out.back() = order[k];
  return out;
}

// Up to `count` particles of `body` near `point` (world) whose directions from it
// span space as evenly as they can (greedy: each pick maximises det Σ û ûᵀ), so
// that LS from them hold the point in every direction: the nearest few of a
// lattice face lie in a plane and would let it move off that plane.
std::vector<int> spread(const Body& body, const Vec3& point, std::size_t count,
                        const std::vector<int>& skip) {
  const std::vector<int> candidates =
      nearest(body, point, std::max<std::size_t>(4 * count, 16), skip);
  std::vector<int> out;
  double m[3][3]{};
  const auto det = [](const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  while (out.size() < count && out.size() < candidates.size()) {
    int best = -1;
    double bestScore = -1.0;
    for (int c : candidates) {
      if (std::find(out.begin(), out.end(), c) != out.end()) continue;
      const Vec3 d = body.world[static_cast<std::size_t>(c)] - point;
      const double u[3] = {d.x / norm(d), d.y / norm(d), d.z / norm(d)};
      double trial[3][3];
      for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) trial[r][k] = m[r][k] + u[r] * u[k] + (r == k ? 0.05 : 0.0);
      // Nearer partners first among equals: a small preference by distance.
      const double score = det(trial) / (1.0 + 0.01 * norm(d) / (norm(d) + 1e-12));
      if (score > bestScore + 1e-12) {
        bestScore = score;
        best = c;
      }
    }
    if (best < 0) break;
    const Vec3 d = body.world[static_cast<std::size_t>(best)] - point;
    const double u[3] = {d.x / norm(d), d.y / norm(d), d.z / norm(d)};
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) m[r][k] += u[r] * u[k];
    out.push_back(best);
  }
  return out;
}

// The inertia a joint's servo moves on one side (MODEL §1.7): about the axis n through
// the body's centre for a revolute joint, 1 / (nᵀ I⁻¹ n) (kg·m²); along n through
// `point` for a prismatic one, 1 / (1/M + (r × n)ᵀ I⁻¹ (r × n)) (kg). Infinity for a
// body with fixed particles (the base: it does not move).
double servoInertia(const Body& body, const Vec3& n, const Vec3& point, bool revolute, bool fixed) {
  if (fixed) return std::numeric_limits<double>::infinity();
  const GeneratedObject& g = body.built.object;
  const MassProperties p = massProperties(body.world, g.mass);
  const Inertia& i = p.inertia;
  Eigen::Matrix3d a;
  a << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  a += 1e-9 * a.trace() * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d inverse = a.inverse();
  const auto quadratic = [&](const Vec3& v) {
    const Eigen::Vector3d e(v.x, v.y, v.z);
    return e.dot(inverse * e);
  };
  if (revolute) return 1.0 / quadratic(n);
  return 1.0 / (1.0 / p.mass + quadratic(cross(point - p.centerOfMass, n)));
}

// What a body link's penalty springs move on one side (MODEL §1.7): the least
// effective mass (kg) of the body's point `point` in any direction,
// 1 / λmax(1/M − [r]× I⁻¹ [r]×), and its least inertia (kg·m²) for turns normal to
// `n` (revolute) or any turn, 1 / λmax(P I⁻¹ P). Infinity for a fixed body.
std::pair<double, double> linkInertia(const Body& body, const Vec3& n, const Vec3& point,
                                      bool normalOnly, bool fixed) {
  const double infinity = std::numeric_limits<double>::infinity();
  if (fixed) return {infinity, infinity};
  const MassProperties p = massProperties(body.world, body.built.object.mass);
  const Inertia& i = p.inertia;
  Eigen::Matrix3d a;
  a << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  a += 1e-9 * a.trace() * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d inverse = a.inverse();
  const Vec3 r = point - p.centerOfMass;
  Eigen::Matrix3d cr;
  cr << 0, -r.z, r.y, r.z, 0, -r.x, -r.y, r.x, 0;
  const Eigen::Matrix3d k = Eigen::Matrix3d::Identity() / p.mass - cr * inverse * cr;
  const Eigen::Vector3d e(n.x, n.y, n.z);
  const Eigen::Matrix3d project =
      normalOnly ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - e * e.transpose())
                 : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d turn = project * inverse * project;
  const double largestK = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(k).eigenvalues()(2);
  const double largestTurn = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(turn).eigenvalues()(2);
  return {1.0 / largestK, 1.0 / largestTurn};
}

// docs/contact.md "Round wheels": a link whose one <collision> is a cylinder coaxial
// with the revolute or continuous joint that carries it meets the environment as
// that cylinder (RimRing::isCylinder), so that it rolls on its true radius, not as
// a polygon of particle bumps. `hub` and `axisPoint` are the joint's axis
// particles c and d = c + w n̂ (body-local), `local` maps body-local indices to the
// link object's; the ring covers the link object's particles (not its carriers).
void addRoundWheel(const Body& body, const UJoint& joint, int hub, int axisPoint,
                   const std::vector<UrdfParticle>& local, int object, ObjectPlacement& placement,
                   UrdfLink& out) {
  if (joint.type != UJoint::Type::kRevolute && joint.type != UJoint::Type::kContinuous) return;
  if (body.spec.shapes.size() != 1 || body.spec.shapes[0].kind != ShapeSpec::Kind::kCylinder)
    return;
  const auto at = [&](int i) { return local[static_cast<std::size_t>(i)]; };
  if (at(hub).object != object || at(axisPoint).object != object) return;
  const ShapeSpec& cylinder = body.spec.shapes[0];
  const Vec3 c = body.world[static_cast<std::size_t>(hub)];
  const Vec3 n = (body.world[static_cast<std::size_t>(axisPoint)] - c) /
                 norm(body.world[static_cast<std::size_t>(axisPoint)] - c);
  ShapeSpec placed = cylinder;  // in the world, as the joint's line
  placed.frame = body.frame.then(cylinder.frame);
  if (roundAbout(placed, c, n) != RoundAbout::kCylinder) {
    out.notes.push_back("not a round wheel: its cylinder is not coaxial with joint '" + joint.name +
                        "' (it touches as its particles)");
    return;
  }
  RimRing wheel;
  wheel.first = 0;
  wheel.count = static_cast<std::int32_t>(placement.geometry.size());
  wheel.hub = at(hub).local;
  wheel.axisParticle = at(axisPoint).local;
  wheel.sphereRadius = cylinder.radius;
  wheel.halfLength = 0.5 * cylinder.length;
  wheel.axialOffset = dot(placed.frame.origin - c, n);
  placement.geometry.rims.push_back(wheel);
  out.roundWheel = true;
  out.notes.push_back("round wheel: meets the environment as its cylinder (radius " +
                      check::number(cylinder.radius) + " m, length " +
                      check::number(cylinder.length) + " m) about joint '" + joint.name + "'");
}

// Whether a continuous joint is a wheel (build::roundAbout): one of its child's
// shapes round about its line, `hub` and `axisPoint` its axis particles (body-local).
bool isWheel(const Body& body, const UJoint& joint, int hub, int axisPoint) {
  if (joint.type != UJoint::Type::kContinuous) return false;
  const Vec3 c = body.world[static_cast<std::size_t>(hub)];
  const Vec3 along = body.world[static_cast<std::size_t>(axisPoint)] - c;
  if (!(norm(along) > 0.0)) return false;
  return std::any_of(body.spec.shapes.begin(), body.spec.shapes.end(), [&](const ShapeSpec& shape) {
    ShapeSpec placed = shape;
    placed.frame = body.frame.then(shape.frame);
    return roundAbout(placed, c, along / norm(along)) != RoundAbout::kNone;
  });
}

}  // namespace

UrdfRobot makeUrdfRobot(const UrdfSpec& spec) {
  if (spec.path.empty())
    check::fail(kUrdfSpec, "file", "'file' (the URDF's path) must not be empty");
  check::nonNegative(kUrdfSpec, "particleSize", spec.particleSize, "m");
  check::atLeast(kUrdfSpec, "particlesPerLink", spec.particlesPerLink, 1);
  check::positive(kUrdfSpec, "naturalFrequency", spec.naturalFrequency, "rad/s");
  check::nonNegative(kUrdfSpec, "servoFrequency", spec.servoFrequency, "rad/s");
  check::finite(kUrdfSpec, "position", spec.placement.origin, "m");
  const double servoFrequency =
      spec.servoFrequency > 0.0 ? spec.servoFrequency : 0.3 * spec.naturalFrequency;
  const Description d = urdf::readUrdf(spec.path, spec.packagePaths);
  const std::string& file = d.file;
  const std::size_t linkCount = d.links.size();

  UrdfRobot robot;
  robot.name = d.robotName;
  robot.file = file;
  robot.warnings = d.warnings;
  const std::string prefix = spec.name.empty() ? d.robotName : spec.name;
  robot.visuals = urdfVisuals(d, prefix);

  // Joint positions the robot is built at.
  std::vector<double> q(d.joints.size(), 0.0);
  for (const auto& [name, value] : spec.initialPositions) {
    std::size_t k = 0;
    while (k < d.joints.size() && d.joints[k].name != name) ++k;
    if (k == d.joints.size() || d.joints[k].type == UJoint::Type::kFixed)
      check::fail(kUrdfSpec, "initialPositions",
                  "'initialPositions': '" + name + "' is not a moving joint of " + file);
    check::finite(kUrdfSpec, "initialPositions", value, "rad or m");
    const UJoint& j = d.joints[k];
    if (j.type != UJoint::Type::kContinuous && (value < j.lower || value > j.upper))
      check::fail(kUrdfSpec, "initialPositions",
                  "'initialPositions': '" + name + "' = " + check::number(value) +
                      " is outside its limits [" + check::number(j.lower) + ", " +
                      check::number(j.upper) + "]");
    q[k] = value;
  }

  // Link frames at the build pose (URDF: X_child = X_parent · origin · motion(q)).
  std::vector<Frame> frame(linkCount);
  frame[static_cast<std::size_t>(d.root)] = spec.placement;
  robot.joints.resize(d.joints.size());
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    const UJoint& j = d.joints[k];
    const Frame jointFrame =
        frame[static_cast<std::size_t>(j.parentIndex)].then(originFrame(j.origin));
    Frame motion;
    if (j.type == UJoint::Type::kRevolute || j.type == UJoint::Type::kContinuous)
      motion = Frame::fromAxisAngle(j.axis, q[k]);
    if (j.type == UJoint::Type::kPrismatic) motion = translation(j.axis * q[k]);
    frame[static_cast<std::size_t>(j.childIndex)] = jointFrame.then(motion);
    UrdfJoint& out = robot.joints[k];
    out.name = j.name;
    out.line = j.line;
    out.type = typeOf(j.type);
    out.axis = j.axis;
    out.worldAxis = jointFrame.rotate(j.axis);
    out.parent = j.parentIndex;
    out.child = j.childIndex;
    out.hasPositionLimits =
        j.hasLimit && (j.type == UJoint::Type::kRevolute || j.type == UJoint::Type::kPrismatic);
    out.lower = j.lower;
    out.upper = j.upper;
    out.velocity = j.velocity;
    out.effort = j.effort;
    out.damping = j.damping;
    out.friction = j.friction;
    out.hasMimic = j.hasMimic;
    out.mimicJoint = j.mimicJoint;
    out.multiplier = j.multiplier;
    out.offset = j.offset;
    out.initialPosition = q[k];
    if (j.type != UJoint::Type::kFixed) out.modelJoint = prefix + "." + j.name;
  }

  // Which links carry particles, and which move with another (MODEL §1: an
  // object respects its reference's mass): a link of mass > 0 has its own; a
  // massless link on a fixed joint is a frame of its parent's body; a massless
  // link on a moving joint (or a massless root) moves with the first massive
  // link fixed below it, and is an error without one (a fixed base without mass
  // gets notional particles).
  const auto massive = [&](int l) {
    const urdf::Link& link = d.links[static_cast<std::size_t>(l)];
    return link.inertial.present && link.inertial.mass > 0.0;
  };
  std::vector<std::vector<int>> fixedChildren(linkCount);
  for (const UJoint& j : d.joints)
    if (j.type == UJoint::Type::kFixed)
      fixedChildren[static_cast<std::size_t>(j.parentIndex)].push_back(j.childIndex);
  const auto massiveBelow = [&](int l) {
    std::vector<int> queue{l};
    for (std::size_t k = 0; k < queue.size(); ++k) {
      if (massive(queue[k])) return queue[k];
      for (int c : fixedChildren[static_cast<std::size_t>(queue[k])]) queue.push_back(c);
    }
    return -1;
  };
  std::vector<int> attached(linkCount, -1);
  std::vector<bool> notional(linkCount, false);
  std::vector<int> order{d.root};
  for (const UJoint& j : d.joints) order.push_back(j.childIndex);
  for (int l : order) {
    const auto li = static_cast<std::size_t>(l);
    const int pj = d.parentJoint[li];
    if (massive(l)) {
      attached[li] = l;
    } else if (pj >= 0 && d.joints[static_cast<std::size_t>(pj)].type == UJoint::Type::kFixed &&
               attached[static_cast<std::size_t>(
                   d.joints[static_cast<std::size_t>(pj)].parentIndex)] >= 0) {
      attached[li] =
          attached[static_cast<std::size_t>(d.joints[static_cast<std::size_t>(pj)].parentIndex)];
    } else if (const int below = massiveBelow(l); below >= 0) {
      attached[li] = below;
    } else if (pj < 0 && spec.fixedBase) {
      attached[li] = l;
      notional[li] = true;
    } else {
      const urdf::Link& link = d.links[li];
      const int line = link.inertial.present ? link.inertial.line : link.line;
      if (pj < 0)
        throw UrdfError(file, line,
                        "link '" + link.name +
                            "' (the root) has no mass and nothing of mass is fixed to it: a free "
                            "base needs mass (or import it with a fixed base)");
      const UJoint& j = d.joints[static_cast<std::size_t>(pj)];
      throw UrdfError(file, line,
                      "link '" + link.name + "' has " +
                          (link.inertial.present ? "mass " + check::number(link.inertial.mass)
                                                 : std::string("no <inertial>")) +
                          " but moves (" + j.typeName + " joint '" + j.name + "', line " +
                          std::to_string(j.line) +
                          "), and no link of mass is fixed to it: give it an <inertial> with "
                          "mass > 0");
    }
  }

  // The size budgets before a link is read or filled (docs/scene-format.md#limits).
  const auto bodyCount =
      static_cast<std::size_t>(std::count_if(order.begin(), order.end(), [&](int l) {
        return attached[static_cast<std::size_t>(l)] == l;
      }));
  if (bodyCount > static_cast<std::size_t>(kMaxUrdfBodies)) {
    // Named at the first link past it (its line).
    std::size_t seen = 0;
    int past = order.front();
    for (const int l : order)
      if (attached[static_cast<std::size_t>(l)] == l && ++seen == kMaxUrdfBodies + 1u) {
        past = l;
        break;
      }
    const urdf::Link& first = d.links[static_cast<std::size_t>(past)];
    throw UrdfError(file, first.line,
                    std::to_string(bodyCount) + " links carry particles, more than the budget of " +
                        std::to_string(kMaxUrdfBodies) +
                        " links of a robot (docs/scene-format.md#limits): link '" + first.name +
                        "' is the first past it");
  }
  if (spec.particleSize == 0.0 &&
      static_cast<double>(bodyCount) * spec.particlesPerLink > kMaxParticlesPerObject)
    throw UrdfError(file, 0,
                    std::to_string(bodyCount) + " links of about " +
                        std::to_string(spec.particlesPerLink) +
                        " particles (particlesPerLink) make more than the budget of " +
                        std::to_string(kMaxParticlesPerObject) +
                        " particles (docs/scene-format.md#limits): give fewer particlesPerLink");

  // Bodies: one per link with particles.
  double massSum = 0.0;
  int massCount = 0;
  for (std::size_t l = 0; l < linkCount; ++l)
    if (massive(static_cast<int>(l))) {
      massSum += d.links[l].inertial.mass;
      ++massCount;
    }
  robot.notionalMass = massCount > 0 ? massSum / massCount : 1.0;
  std::vector<Body> bodies;
  std::vector<int> bodyOf(linkCount, -1);
  robot.links.resize(linkCount);
  for (int l : order) {
    const auto li = static_cast<std::size_t>(l);
    const urdf::Link& link = d.links[li];
    UrdfLink& out = robot.links[li];
    out.name = link.name;
    out.line = link.line;
    out.attachedTo = attached[li];
    out.frame = frame[li];
    out.declared = declaredOf(link);
    out.declaredWorld = toWorld(out.declared, frame[li]);
    out.notional = notional[li];
    if (attached[li] != l) continue;
    Body body;
    body.link = l;
    body.frame = frame[li];
    for (const urdf::Collision& c : link.collisions) body.spec.shapes.push_back(shapeOf(c, file));
    if (notional[li]) {
      body.spec.mass = robot.notionalMass;
      body.spec.uniformDensity = !body.spec.shapes.empty();
    } else {
      body.spec.mass = out.declared.mass;
      body.spec.centerOfMass = out.declared.centerOfMass;
      body.spec.inertia = out.declared.inertia;
    }
    body.spec.particleSize = spec.particleSize;
    body.spec.particleCount = spec.particlesPerLink;
    body.spec.naturalFrequency = spec.naturalFrequency;
    // Size and spacing estimates (the joints' arms are about a lattice spacing).
    Vec3 low{1e300, 1e300, 1e300}, high = low * -1.0;
    for (const ShapeSpec& s : body.spec.shapes) extend(s, low, high);
    double volume = 0.0;
    if (body.spec.shapes.empty()) {
      body.size = 0.0;
    } else {
      const Vec3 side = high - low;
      body.size = norm(side);
      volume = std::max(side.x, 1e-3) * std::max(side.y, 1e-3) * std::max(side.z, 1e-3);
    }
    body.spacing = spec.particleSize > 0.0
                       ? spec.particleSize
                       : (volume > 0.0 ? std::cbrt(volume / spec.particlesPerLink) : 0.02);
    bodyOf[li] = static_cast<int>(bodies.size());
    bodies.push_back(std::move(body));
  }
  for (std::size_t l = 0; l < linkCount; ++l)
    if (bodyOf[l] < 0) bodyOf[l] = bodyOf[static_cast<std::size_t>(attached[l])];
  // Joint particles (required points of the bodies), before the bodies are built.
  struct Plan {
    int joint = -1, parent = -1, child = -1;  // joint index, body indices
    double arm = 0.0;
    std::vector<int> parentPoints, childPoints;  // indices into requiredPoints
    Vec3 axis{};
  };
  std::vector<Plan> plans;
  for (std::size_t k = 0; k < d.joints.size(); ++k) {
    const UJoint& j = d.joints[k];
    Plan plan;
    plan.joint = static_cast<int>(k);
    plan.parent = bodyOf[static_cast<std::size_t>(j.parentIndex)];
    plan.child = bodyOf[static_cast<std::size_t>(j.childIndex)];
    if (plan.parent == plan.child) continue;  // a frame on its parent's body
    Body& parent = bodies[static_cast<std::size_t>(plan.parent)];
    Body& child = bodies[static_cast<std::size_t>(plan.child)];
    const Frame jointFrame =
        frame[static_cast<std::size_t>(j.parentIndex)].then(originFrame(j.origin));
    const Vec3 n = jointFrame.rotate(j.axis);
    plan.axis = n;
    plan.arm = std::max({1.5 * std::min(parent.spacing, child.spacing), 0.01});
    const double w = plan.arm;
    const Vec3 u = normalTo(n), v = cross(n, u);
    const Vec3 c = jointFrame.origin;
    if (j.type == UJoint::Type::kRevolute || j.type == UJoint::Type::kContinuous) {
      // MODEL §1.4 revolute: c, d on the axis and b in the plane through c (child); a (parent).
      plan.childPoints = {child.require(c), child.require(c + n * w), child.require(c + u * w)};
      plan.parentPoints = {parent.require(c + v * w)};
    } else if (j.type == UJoint::Type::kPrismatic) {
      // Two sliders s1, s2 on the line and a roll arm b (child); origin, end and
      // the roll lock's arm a (parent), the line covering the whole stroke.
      const double lower = std::min(j.lower, q[k]), upper = std::max(j.upper, q[k]);
      const Vec3 s1 = c + n * q[k];
      plan.childPoints = {child.require(s1), child.require(s1 + n * (2 * w)),
                          child.require(s1 + u * w)};
      plan.parentPoints = {parent.require(c + n * (lower - w)),
                           parent.require(c + n * (upper + 3 * w)), parent.require(c + v * w)};
    }
    plans.push_back(plan);
  }

  // Fill the bodies (makeRigidBody: mass, centre and inertia fitted), their
  // particles held to the budget as they are made (at most one link past it).
  std::size_t particles = 0, connectors = 0;
  for (Body& body : bodies) {
    const urdf::Link& link = d.links[static_cast<std::size_t>(body.link)];
    try {
      body.built = makeRigidBody(body.spec);
    } catch (const SpecError& error) {
      throw UrdfError(file, link.line,
                      "link '" + link.name + "' cannot be filled: " + error.message());
    }
    particles += body.built.object.size();
    if (particles > static_cast<std::size_t>(kMaxParticlesPerObject))
      throw UrdfError(file, link.line,
                      "link '" + link.name + "' brings the robot to " + std::to_string(particles) +
                          " particles, more than the budget of " +
                          std::to_string(kMaxParticlesPerObject) +
                          " (docs/scene-format.md#limits): give a larger particleSize");
    // The connectors too (a bare URDF's model is built from them: the scene
    // loader's budget of a scene, checked here before anything is placed).
    connectors += body.built.object.linearSprings.size() + body.built.object.torsionSprings.size() +
                  body.built.object.jointSprings.size();
    if (connectors > static_cast<std::size_t>(kMaxConnectorsPerObject))
      throw UrdfError(file, link.line,
                      "link '" + link.name + "' brings the robot to " + std::to_string(connectors) +
                          " connectors, more than the budget of " +
                          std::to_string(kMaxConnectorsPerObject) +
                          " (docs/scene-format.md#limits): give fewer links or particles");
    for (const Vec3& p : body.built.object.position) body.world.push_back(body.frame.apply(p));
    const auto& springs = body.built.object.linearSprings;
    if (!springs.empty()) {
      body.stiffness = springs.front().stiffness;
      body.damping = springs.front().damping;
    }
    UrdfLink& out = robot.links[static_cast<std::size_t>(body.link)];
    out.achieved = body.built.achieved;
    out.notes = body.built.notes;
    if (out.notional)
      out.notes.push_back("notional base: the URDF gives it no mass; " +
                          check::number(robot.notionalMass) +
                          " kg (the mean link mass) of uniform density");
  }
  // Connector stiffness between two bodies: the softer body's LS (N/m, N·s/m).
  const auto tie = [&](int a, int b) {
    const Body& x = bodies[static_cast<std::size_t>(a)];
    const Body& y = bodies[static_cast<std::size_t>(b)];
    const double kx = x.stiffness > 0.0 ? x.stiffness : y.stiffness;
    const double ky = y.stiffness > 0.0 ? y.stiffness : x.stiffness;
    const double dx = x.stiffness > 0.0 ? x.damping : y.damping;
    const double dy = y.stiffness > 0.0 ? y.damping : x.damping;
    return kx <= ky ? std::pair{kx, dx} : std::pair{ky, dy};
  };
  const auto at = [&](int body, int local) { return UrdfParticle{body, local}; };
  const auto position = [&](const UrdfParticle& p) {
    return bodies[static_cast<std::size_t>(p.object)].world[static_cast<std::size_t>(p.local)];
  };
  const auto link = [&](const UrdfParticle& a, const UrdfParticle& b, double k, double mu) {
    robot.linearSprings.push_back({a, b, norm(position(a) - position(b)), k, mu});
    return static_cast<int>(robot.linearSprings.size()) - 1;
  };
  // A body link between the plan's two bodies: gains κ = ω² m for the pair's reduced
  // mass (and inertia), so that the pair's own frequency is ω, critically damped.
  const int fixedBody = bodyOf[static_cast<std::size_t>(d.root)];
  const auto addBodyLink = [&](const Plan& plan, BodyLinkKind kind, const Vec3& point) {
    UrdfBodyLink held;
    held.kind = kind;
    held.child = bodies[static_cast<std::size_t>(plan.child)].link;
    held.parent = bodies[static_cast<std::size_t>(plan.parent)].link;
    held.point = point;
    held.axis = plan.axis;
    const bool normalOnly = kind == BodyLinkKind::kRevolute;
    const auto [mc, ic] = linkInertia(bodies[static_cast<std::size_t>(plan.child)], plan.axis,
                                      point, normalOnly, spec.fixedBase && plan.child == fixedBody);
    const auto [mp, ip] =
        linkInertia(bodies[static_cast<std::size_t>(plan.parent)], plan.axis, point, normalOnly,
                    spec.fixedBase && plan.parent == fixedBody);
    // The pair's reduced mass and inertia (a fixed side adds 0 to their inverses).
    const double w2 = servoFrequency * servoFrequency;
    const double m = 1.0 / (1.0 / mc + 1.0 / mp), i = 1.0 / (1.0 / ic + 1.0 / ip);
    if (std::isfinite(m)) {
      held.gains.stiffness = w2 * m;
      held.gains.damping = 2.0 * std::sqrt(held.gains.stiffness * m);
    }
    if (std::isfinite(i)) {
      held.gains.angularStiffness = w2 * i;
      held.gains.angularDamping = 2.0 * std::sqrt(held.gains.angularStiffness * i);
    }
    robot.bodyLinks.push_back(held);
    return static_cast<int>(robot.bodyLinks.size()) - 1;
  };
  for (const Plan& plan : plans) {
    const UJoint& j = d.joints[static_cast<std::size_t>(plan.joint)];
    UrdfJoint& out = robot.joints[static_cast<std::size_t>(plan.joint)];
    const Body& parent = bodies[static_cast<std::size_t>(plan.parent)];
    const Body& child = bodies[static_cast<std::size_t>(plan.child)];
    const auto [k, mu] = tie(plan.parent, plan.child);
    const double w = plan.arm;
    const auto childPoint = [&](int r) {
      return at(plan.child, child.built.required[static_cast<std::size_t>(plan.childPoints[r])]);
    };
    const auto parentPoint = [&](int r) {
      return at(plan.parent, parent.built.required[static_cast<std::size_t>(plan.parentPoints[r])]);
    };
    if (j.type == UJoint::Type::kFixed) {
      const Frame jointFrame =
          frame[static_cast<std::size_t>(j.parentIndex)].then(originFrame(j.origin));
      addBodyLink(plan, BodyLinkKind::kFixed, jointFrame.origin);
      // The child tied rigidly to its parent: its particles nearest the parent to
      // the parent's three nearest, and the other way round.
      for (const auto& [from, to] :
           {std::pair{plan.child, plan.parent}, std::pair{plan.parent, plan.child}}) {
        const Body& a = bodies[static_cast<std::size_t>(from)];
        const Body& b = bodies[static_cast<std::size_t>(to)];
        std::vector<std::pair<double, int>> distance;
        for (int i = 0; i < static_cast<int>(a.world.size()); ++i) {
          double best = std::numeric_limits<double>::infinity();
          for (const Vec3& p : b.world)
            best = std::min(best, norm(p - a.world[static_cast<std::size_t>(i)]));
          distance.emplace_back(best, i);
        }
        std::stable_sort(distance.begin(), distance.end());
        for (std::size_t m = 0; m < std::min<std::size_t>(4, distance.size()); ++m) {
          const int i = distance[m].second;
          for (int partner : nearest(b, a.world[static_cast<std::size_t>(i)], 3))
            link(at(from, i), at(to, partner), k, mu);
        }
      }
      continue;
    }
    if (j.type == UJoint::Type::kPrismatic) {
      const UrdfParticle s1 = childPoint(0), s2 = childPoint(1), b = childPoint(2);
      const UrdfParticle o = parentPoint(0), e = parentPoint(1), a = parentPoint(2);
      // MODEL §1.2: a TS at 180° acts on its centre like a lateral spring of
      // κ (1/|u| + 1/|w|)²; each slider's is made the links' κ at the build pose.
      for (const UrdfParticle& slider : {s1, s2}) {
        const double lateral =
            1.0 / norm(position(o) - position(slider)) + 1.0 / norm(position(e) - position(slider));
        robot.torsionSprings.push_back(
            {o, slider, e, std::numbers::pi, k / (lateral * lateral), mu / (lateral * lateral)});
      }
      const int connector = static_cast<int>(robot.torsionSprings.size()) - 2;
      // The roll lock: a JS about the slider line, as stiff as the links at its arm.
      robot.jointSprings.push_back(
          {a, s1, b, s2, jointAngle(position(a), position(s1), position(b), position(s2)),
           k * w * w, mu * w * w});
      // The drive LS measures q; the servo and the losses act through the bodies.
      const int drive = link(o, s1, 0.0, 0.0);
      const double lowerEnd = std::min(j.lower, q[static_cast<std::size_t>(plan.joint)]) - w;
      UrdfModelJoint model{out.modelJoint, JointKind::kPrismatic, connector, drive, -lowerEnd};
      model.servoTarget = norm(position(s1) - position(o));
      robot.modelJoints.push_back(model);
    } else {
      const UrdfParticle c = childPoint(0), dd = childPoint(1), b = childPoint(2);
      const UrdfParticle a = parentPoint(0);
      // The parent holds the axis: c and d each tied to 6 parent particles spread
      // around it (a among them), so that the child turns about the line c–d only.
      for (const UrdfParticle& axisPoint : {c, dd}) {
        std::vector<int> partners = spread(parent, position(axisPoint), 5, {a.local});
        partners.push_back(a.local);
        for (int partner : partners) link(at(plan.parent, partner), axisPoint, k, mu);
      }
      // MODEL §1.3 JS a-c-b-d: it measures q; the servo and the URDF's damping act
      // through the bodies (MODEL §1.7: on one light arm particle, damping of 0.5
      // N·m·s/rad needs steps of 5e-6 s).
      const double angle = jointAngle(position(a), position(c), position(b), position(dd));
      robot.jointSprings.push_back({a, c, b, dd, angle, 0.0, 0.0});
      UrdfModelJoint model{out.modelJoint, JointKind::kRevolute,
                           static_cast<int>(robot.jointSprings.size()) - 1, -1,
                           wrapAngle(angle - q[static_cast<std::size_t>(plan.joint)])};
      model.servoTarget = angle;
      robot.modelJoints.push_back(model);
    }
    // The hold gains (MODEL §1.7): κ = ω² I of the side that moves more easily,
    // critically damped (β = 2 √(κ I)).
    const bool revolute = j.type != UJoint::Type::kPrismatic;
    const Vec3 point = position(childPoint(0));
    // The pair's reduced inertia: 1 / (1/I_child + 1/I_parent), a fixed side adding 0.
    const double inertia = 1.0 / (1.0 / servoInertia(child, plan.axis, point, revolute,
                                                     spec.fixedBase && plan.child == fixedBody) +
                                  1.0 / servoInertia(parent, plan.axis, point, revolute,
                                                     spec.fixedBase && plan.parent == fixedBody));
    UrdfModelJoint& model = robot.modelJoints.back();
    model.drive.damping = j.damping;
    model.drive.friction = j.friction;
    if (j.hasLimit && j.effort > 0.0) model.drive.effortLimit = j.effort;
    if (j.hasLimit && j.velocity > 0.0) model.drive.velocityLimit = j.velocity;
    if (std::isfinite(inertia)) {
      out.holdStiffness = servoFrequency * servoFrequency * inertia;
      out.holdDamping = 2.0 * std::sqrt(out.holdStiffness * inertia);
    }
    if (spec.holdJoints) {
      model.servoStiffness = out.holdStiffness;
      model.servoDamping = out.holdDamping;
    }
    model.bodyLink =
        addBodyLink(plan, revolute ? BodyLinkKind::kRevolute : BodyLinkKind::kPrismatic, point);
  }

  // The objects, in the world, and who touches whom. A body's carriers (mass
  // beyond its geometry, possibly far outside it) are an object of kind
  // "virtual" of their own: they carry inertia and touch nothing.
  std::vector<std::vector<UrdfParticle>> renumber(bodies.size());
  std::vector<UrdfLinearSpring> carrierTies;
  const auto objectCount = static_cast<int>(bodies.size());
  std::vector<ObjectPlacement> carrierObjects;
  std::vector<std::vector<std::size_t>> plansOfChild(bodies.size());
  for (std::size_t k = 0; k < plans.size(); ++k)
    plansOfChild[static_cast<std::size_t>(plans[k].child)].push_back(k);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    Body& body = bodies[b];
    UrdfLink& out = robot.links[static_cast<std::size_t>(body.link)];
    out.object = static_cast<int>(b);
    const GeneratedObject& g = body.built.object;
    std::vector<bool> carrier(g.size(), false);
    for (int c : body.built.carriers) carrier[static_cast<std::size_t>(c)] = true;
    const bool fixed = spec.fixedBase && body.link == attached[static_cast<std::size_t>(d.root)];
    ObjectPlacement placement, carriers;
    placement.name = prefix + "." + d.links[static_cast<std::size_t>(body.link)].name;
    placement.kind = "link";
    carriers.name = placement.name + ".carriers";
    carriers.kind = "virtual";
    carriers.geometry.contact.touches = false;
    const int carrierObject = objectCount + static_cast<int>(carrierObjects.size());
    renumber[b].resize(g.size());
    for (std::size_t i = 0; i < g.size(); ++i) {
      ObjectPlacement& into = carrier[i] ? carriers : placement;
      renumber[b][i] = {carrier[i] ? carrierObject : static_cast<int>(b),
                        static_cast<int>(into.geometry.size())};
      into.geometry.position.push_back(body.world[i]);
      into.geometry.mass.push_back(g.mass[i]);
      into.geometry.radius.push_back(g.radius[i]);
      into.geometry.fixed.push_back(fixed || (!g.fixed.empty() && g.fixed[i]));
    }
    for (const LinearSpring& ls : g.linearSprings) {
      const UrdfParticle a = renumber[b][static_cast<std::size_t>(ls.a)];
      const UrdfParticle bb = renumber[b][static_cast<std::size_t>(ls.b)];
      if (a.object == bb.object) {
        ObjectPlacement& into = a.object == static_cast<int>(b) ? placement : carriers;
        into.geometry.linearSprings.push_back(
            {a.local, bb.local, ls.restLength, ls.stiffness, ls.damping});
      } else {
        carrierTies.push_back({a, bb, ls.restLength, ls.stiffness, ls.damping});
      }
    }
    placement.geometry.spacing = g.spacing;
    placement.geometry.rigid = true;
    for (const std::size_t k : plansOfChild[b]) {
      const Plan& plan = plans[k];
      if (plan.childPoints.size() < 2) continue;
      const UJoint& joint = d.joints[static_cast<std::size_t>(plan.joint)];
      const int hub = body.built.required[static_cast<std::size_t>(plan.childPoints[0])];
      const int axisPoint = body.built.required[static_cast<std::size_t>(plan.childPoints[1])];
      robot.joints[static_cast<std::size_t>(plan.joint)].wheel = isWheel(body, joint, hub, axisPoint);
      if (spec.roundWheels)
        addRoundWheel(body, joint, hub, axisPoint, renumber[b], static_cast<int>(b), placement, out);
    }
    robot.objects.push_back(std::move(placement));
    if (!carriers.geometry.position.empty()) {
      out.carrierObject = carrierObject;
      carrierObjects.push_back(std::move(carriers));
    }
  }
  // The connectors so far named (body, local index in its RigidBody).
  const auto remap = [&](UrdfParticle& p) {
    p = renumber[static_cast<std::size_t>(p.object)][static_cast<std::size_t>(p.local)];
  };
  for (UrdfLinearSpring& ls : robot.linearSprings) {
    remap(ls.a);
    remap(ls.b);
  }
  for (UrdfTorsionSpring& ts : robot.torsionSprings) {
    remap(ts.a);
    remap(ts.c);
    remap(ts.b);
  }
  for (UrdfJointSpring& js : robot.jointSprings) {
    remap(js.a);
    remap(js.c);
    remap(js.b);
    remap(js.d);
  }
  robot.linearSprings.insert(robot.linearSprings.end(), carrierTies.begin(), carrierTies.end());
  robot.bodyFrequency = servoFrequency;
  robot.compensateGravity = spec.holdJoints;
  robot.bodyDampingRatio = 0.5;
  for (ObjectPlacement& o : carrierObjects) robot.objects.push_back(std::move(o));
  for (UrdfLink& each : robot.links)
    if (each.object < 0)
      each.object = robot.links[static_cast<std::size_t>(each.attachedTo)].object;
  if (!spec.selfCollision) {
    robot.noContactWithin = objectCount;
  } else {
    std::set<std::array<int, 2>> pairs;
    for (const Plan& plan : plans)
      pairs.insert({std::min(plan.parent, plan.child), std::max(plan.parent, plan.child)});
    robot.noContact.assign(pairs.begin(), pairs.end());
  }
  return robot;
}

void translateUrdfRobot(UrdfRobot& robot, const Vec3& offset) {
  check::finite("translateUrdfRobot", "offset", offset, "m");
  for (ObjectPlacement& object : robot.objects)
    for (Vec3& p : object.geometry.position) p = p + offset;
  for (UrdfLink& link : robot.links) {
    link.frame.origin = link.frame.origin + offset;
    link.declaredWorld.centerOfMass = link.declaredWorld.centerOfMass + offset;
  }
}

namespace {

// Each link's bodies at and below it (its own and every link's below it), in
// the order of a breadth-first walk of its subtree by the children lists, as
// lists that share runs: where a link's children but the last are leaves, its
// walk is [it, those leaves] + the last child's walk, so the last child's list is
// a suffix of its own. A run is written from each link that is not such a last
// child: a chain is one run, whose suffixes are all its lists (memory and time
// linear in its links; a list each was their square).
std::vector<BodyList> sharedBodiesBelow(const std::vector<std::vector<int>>& childLinks,
                                        const std::vector<std::int32_t>& bodyOf) {
  const std::size_t links = childLinks.size();
  const auto leaf = [&](int l) { return childLinks[static_cast<std::size_t>(l)].empty(); };
  // Its walk extends its last child's: the children but the last are leaves.
  const auto extends = [&](std::size_t l) {
    const std::vector<int>& children = childLinks[l];
    return !children.empty() && std::all_of(children.begin(), children.end() - 1, leaf);
  };
  std::vector<char> continued(links, 0);  // the last child of a link whose walk extends it
  for (std::size_t l = 0; l < links; ++l)
    if (extends(l)) continued[static_cast<std::size_t>(childLinks[l].back())] = 1;
  std::vector<BodyList> out(links);
  for (std::size_t top = 0; top < links; ++top) {
    if (continued[top]) continue;
    auto run = std::make_shared<std::vector<std::int32_t>>();
    std::vector<std::pair<std::size_t, std::size_t>> starts;  // (link, first in run)
    const auto emit = [&](std::size_t l) {
      if (bodyOf[l] >= 0) run->push_back(bodyOf[l]);
    };
    std::size_t l = top;
    for (;;) {
      starts.emplace_back(l, run->size());
      emit(l);
      if (!extends(l)) {
        // The rest of its walk, breadth first.
        std::vector<int> queue(childLinks[l].begin(), childLinks[l].end());
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const auto at = static_cast<std::size_t>(queue[q]);
          emit(at);
          queue.insert(queue.end(), childLinks[at].begin(), childLinks[at].end());
        }
        break;
      }
      const std::vector<int>& children = childLinks[l];
      for (std::size_t c = 0; c + 1 < children.size(); ++c)
        emit(static_cast<std::size_t>(children[c]));
      l = static_cast<std::size_t>(children.back());
    }
    const std::shared_ptr<const std::vector<std::int32_t>> shared = std::move(run);
    for (const auto& [link, first] : starts)
      out[link] = BodyList(shared, first, shared->size() - first);
  }
  return out;
}

}  // namespace

PlacedUrdfRobot placeUrdfRobot(ModelBuilder& builder, const UrdfRobot& robot) {
  PlacedUrdfRobot placed;
  for (const ObjectPlacement& object : robot.objects)
    placed.objects.push_back(builder.addObject(object));
  const auto index = [&](const UrdfParticle& p) {
    return placed.objects[static_cast<std::size_t>(p.object)].particle(p.local);
  };
  std::vector<std::int32_t> linear, torsion, joint;
  for (const UrdfLinearSpring& s : robot.linearSprings)
    linear.push_back(builder.addConnector(
        LinearSpring{index(s.a), index(s.b), s.restLength, s.stiffness, s.damping}));
  for (const UrdfTorsionSpring& s : robot.torsionSprings)
    torsion.push_back(builder.addConnector(
        TorsionSpring{index(s.a), index(s.c), index(s.b), s.restAngle, s.stiffness, s.damping}));
  for (const UrdfJointSpring& s : robot.jointSprings)
    joint.push_back(builder.addConnector(JointSpring{index(s.a), index(s.c), index(s.b), index(s.d),
                                                     s.restAngle, s.stiffness, s.damping}));
  // Bodies (MODEL §1.7): each link with particles, with its carriers; then their links.
  placed.body.assign(robot.links.size(), -1);
  for (std::size_t l = 0; l < robot.links.size(); ++l) {
    const UrdfLink& link = robot.links[l];
    if (link.object < 0 || link.attachedTo != static_cast<int>(l)) continue;
    std::vector<ParticleIndex> particles;
    for (int o : {link.object, link.carrierObject}) {
      if (o < 0) continue;
      const PlacedObject& object = placed.objects[static_cast<std::size_t>(o)];
      for (ParticleIndex p = 0; p < object.particleCount; ++p)
        particles.push_back(object.particle(p));
    }
    placed.body[l] =
        builder.addBody(robot.objects[static_cast<std::size_t>(link.object)].name,
                        std::move(particles), robot.bodyFrequency, robot.bodyDampingRatio);
  }
  // The bodies at and below a link (its own and every link's below it), once
  // each: a walk of the link's subtree by its children lists, in time linear in
  // its size (the lists are the model's, one per joint: a chain's sum is n²/2).
  std::vector<std::vector<int>> childLinks(robot.links.size());
  for (const UrdfJoint& j : robot.joints)
    childLinks[static_cast<std::size_t>(j.parent)].push_back(j.child);
  std::vector<int> seenIn;  // body → the last walk that listed it
  int walk = 0;
  const auto bodiesBelow = [&](const std::vector<int>& tops) {
    ++walk;
    std::vector<std::int32_t> out;
    for (int top : tops) {
      std::vector<int> below{top};
      for (std::size_t q = 0; q < below.size(); ++q) {
        const auto l = static_cast<std::size_t>(below[q]);
        below.insert(below.end(), childLinks[l].begin(), childLinks[l].end());
        const std::int32_t b = placed.body[l];
        if (b < 0) continue;
        const auto bi = static_cast<std::size_t>(b);
        if (bi >= seenIn.size()) seenIn.resize(bi + 1, 0);
        if (seenIn[bi] == walk) continue;
        seenIn[bi] = walk;
        out.push_back(b);
      }
    }
    return out;
  };
  const std::vector<BodyList> below = sharedBodiesBelow(childLinks, placed.body);
  std::vector<std::int32_t> bodyLinkOf;
  for (const UrdfBodyLink& link : robot.bodyLinks) {
    BodyLink gains = link.gains;
    // MODEL §1.7: held joints' links carry their weight bodies (the weight preload).
    if (robot.compensateGravity) gains.weightBodies = below[static_cast<std::size_t>(link.child)];
    bodyLinkOf.push_back(builder.addBodyLink(
        link.kind, placed.body[static_cast<std::size_t>(link.child)],
        placed.body[static_cast<std::size_t>(link.parent)], link.point, link.axis, gains));
  }
  // The URDF joints of each model joint (a name → index table, not a search per joint).
  std::map<std::string, std::size_t> modelJointIndex;
  for (std::size_t k = 0; k < robot.modelJoints.size(); ++k)
    modelJointIndex.emplace(robot.modelJoints[k].name, k);
  std::vector<std::vector<int>> urdfJointsOf(robot.modelJoints.size());
  for (const UrdfJoint& u : robot.joints)
    if (const auto found = modelJointIndex.find(u.modelJoint);
        !u.modelJoint.empty() && found != modelJointIndex.end())
      urdfJointsOf[found->second].push_back(u.child);
  std::vector<std::int32_t> modelJointOf;
  for (std::size_t k = 0; k < robot.modelJoints.size(); ++k) {
    const UrdfModelJoint& j = robot.modelJoints[k];
    Joint model;
    model.name = j.name;
    model.kind = j.kind;
    model.connector = j.kind == JointKind::kRevolute
                          ? joint[static_cast<std::size_t>(j.connector)]
                          : torsion[static_cast<std::size_t>(j.connector)];
    model.driveSpring = j.driveSpring >= 0 ? linear[static_cast<std::size_t>(j.driveSpring)] : -1;
    model.zero = j.zero;
    model.servoStiffness = j.servoStiffness;
    model.servoDamping = j.servoDamping;
    model.servoTarget = j.servoTarget;
    model.drive = j.drive;
    if (j.bodyLink >= 0) model.bodyLink = bodyLinkOf[static_cast<std::size_t>(j.bodyLink)];
    // The bodies it carries: its child link's and every link's below it.
    model.subtreeBodies = urdfJointsOf[k].size() == 1
                              ? below[static_cast<std::size_t>(urdfJointsOf[k][0])]
                              : BodyList(bodiesBelow(urdfJointsOf[k]));
    model.compensateGravity = robot.compensateGravity;
    modelJointOf.push_back(builder.addJoint(model));
  }
  for (const UrdfJoint& j : robot.joints) {
    const auto found = modelJointIndex.find(j.modelJoint);
    placed.modelJoint.push_back(
        j.modelJoint.empty() || found == modelJointIndex.end() ? -1 : modelJointOf[found->second]);
  }
  if (robot.noContactWithin > 1) {
    std::vector<std::int32_t> links;
    for (int o = 0; o < robot.noContactWithin; ++o)
      links.push_back(placed.objects[static_cast<std::size_t>(o)].object);
    builder.excludeContactWithin(links);
  }
  for (const auto& [a, b] : robot.noContact)
    builder.excludeContact(placed.objects[static_cast<std::size_t>(a)].object,
                           placed.objects[static_cast<std::size_t>(b)].object);
  placeUrdfVisuals(builder, robot, placed);
  return placed;
}

}  // namespace robophi::build
