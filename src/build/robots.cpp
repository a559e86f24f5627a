// Robot generators: the chain (arm, fingers) and the arm (docs/robotics.md).
// Bodies are small rigid particle sets (complete LS graphs); revolute joints are
// two bodies sharing an axis (centre and axis particles) plus a JS (MODEL §1).
#include "robophi/build/robots.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "build/checks.h"
#include "build/robot_parts.h"
#include "robophi/connector_forces.h"

namespace robophi::build {

namespace {

Vec3 unit(const Vec3& v) { return v / norm(v); }

// A rigid body: LS between every pair of `members`, except pairs both in `skip`.
void rigidBody(GeneratedObject& o, const std::vector<int>& members, const std::vector<int>& skip) {
  const auto in = [](const std::vector<int>& v, int x) {
    return std::find(v.begin(), v.end(), x) != v.end();
  };
  for (std::size_t i = 0; i < members.size(); ++i)
    for (std::size_t j = i + 1; j < members.size(); ++j)
      if (!(in(skip, members[i]) && in(skip, members[j]))) addLink(o, members[i], members[j]);
}

void addJoint(GeneratedObject& o, const std::string& name, int a, int c, int b, int d,
              double stiffness, double damping) {
  const auto& x = o.position;
  const double angle = jointAngle(x[a], x[c], x[b], x[d]);
  o.jointSprings.push_back({a, c, b, d, angle, stiffness, damping});
  o.joints.push_back({name, JointKind::kRevolute,
                      static_cast<std::int32_t>(o.jointSprings.size()) - 1, -1, angle});
}

// Checks what appendChain needs; `spec` names the caller in the messages.
void checkChain(const char* spec, const ChainSpec& chain) {
  check::finite(spec, "base", chain.base, "m");
  check::nonZero(spec, "direction", chain.direction);
  if (chain.links.empty())
    check::fail(spec, "links", "'links': expected a non-empty array of lengths (m)");
  for (double length : chain.links) check::positive(spec, "links", length, "m");
  if (chain.axes.size() != chain.links.size())
    check::fail(spec, "axes",
                "'axes': expected one axis [x, y, z] or " + std::to_string(chain.links.size()) +
                    " of them, got " + std::to_string(chain.axes.size()));
  const Vec3 e = unit(chain.direction);
  for (std::size_t i = 0; i < chain.axes.size(); ++i) {
    const Vec3& axis = chain.axes[i];
    check::finite(spec, "axes", axis, "-");
    if (!(norm(axis) > 0.0) || norm(cross(unit(axis), e)) < 1e-3)
      check::fail(spec, "axes",
                  "'axes': joint " + std::to_string(i + 1) +
                      " axis is zero or parallel to 'direction' (a roll joint is not supported)");
  }
  check::positive(spec, "mass", chain.mass, "kg");
  check::positive(spec, "width", chain.width, "m");
  check::atLeast(spec, "particlesPerLink", chain.particlesPerLink, 2);
  // appendChain: m + 3 particles a link (and 3 at the base); each link is a rigid
  // body of m + 5 particles, an LS between every pair but one, and a JS.
  const double links = static_cast<double>(chain.links.size());
  const double members = chain.particlesPerLink + 5.0;
  check::fitsBudget(spec, "particlesPerLink",
                    "'particlesPerLink' " + std::to_string(chain.particlesPerLink) + " on " +
                        std::to_string(chain.links.size()) + " links",
                    links * (chain.particlesPerLink + 3.0) + 3.0,
                    links * members * (members - 1.0) / 2.0);
  check::nonNegative(spec, "radius", chain.radius, "m");
  check::nonNegative(spec, "jointStiffness", chain.jointStiffness, "N·m/rad");
  check::nonNegative(spec, "jointDamping", chain.jointDamping, "N·m·s/rad");
}

// appendChain takes unit vectors as they are (normalising them again could
// change their last bit, and with it the robot).
void checkUnit(const char* field, const Vec3& v) {
  if (!(std::abs(norm(v) - 1.0) <= 1e-9))
    check::fail("ChainSpec", field,
                "'" + std::string(field) + "' must be a unit vector, got " + check::vector(v));
}

}  // namespace

ChainParts appendChain(GeneratedObject& o, const ChainSpec& spec) {
  checkChain("ChainSpec", spec);
  checkUnit("direction", spec.direction);
  for (const Vec3& axis : spec.axes) checkUnit("axes", axis);
  ChainParts parts;
  const std::size_t n = spec.links.size();
  const Vec3 e = spec.direction;
  const int m = spec.particlesPerLink;
  const double total = std::accumulate(spec.links.begin(), spec.links.end(), 0.0);
  const double w = spec.width;
  double minSpacing = spec.links[0] / m;
  for (double l : spec.links) minSpacing = std::min(minSpacing, l / m);
  const double r = spec.radius > 0.0 ? spec.radius : 0.45 * minSpacing;
  const double small = std::min(r, 0.3 * w);
  const std::vector<Vec3>& axes = spec.axes;
  // Base: joint 1 centre, axis particle, and a reference behind.
  const double baseMass = spec.mass / (static_cast<double>(n) * (m + 3));
  int centre = addParticle(o, spec.base, baseMass, r);
  int axis = addParticle(o, spec.base + axes[0] * w, baseMass, small);
  int parentRef = addParticle(o, spec.base - e * w, baseMass, small);
  parts.base = {centre, axis, parentRef};
  Vec3 joint = spec.base;
  for (std::size_t k = 0; k < n; ++k) {
    const double length = spec.links[k];
    const double linkMass = spec.mass * length / total;
    const double each = linkMass / static_cast<double>(m + 3);
    const Vec3 ax = axes[k];
    const Vec3 v1 = unit(cross(ax, e));
    std::vector<int> body = {centre, axis};
    std::vector<int> line;
    for (int j = 1; j < m; ++j)
      line.push_back(addParticle(o, joint + e * (length * j / m), each, r));
    const Vec3 middle = joint + e * (0.5 * length);
    body.push_back(addParticle(o, middle + v1 * w, each, small));
    body.push_back(addParticle(o, middle + ax * w, each, small));
    const Vec3 next = joint + e * length;
    const int nextCentre = addParticle(o, next, each, r);
    int nextAxis = -1;
    if (k + 1 < n) {
      nextAxis = addParticle(o, next + axes[k + 1] * w, each, small);
    } else {
      // The last link's third brace keeps the tool's body 3-D.
      nextAxis = addParticle(o, next - v1 * w, each, small);
    }
    body.insert(body.end(), line.begin(), line.end());
    body.push_back(nextCentre);
    body.push_back(nextAxis);
    rigidBody(o, body, {centre, axis});
    // MODEL §1 JS: a on the parent body, b on this link; straight is π.
    addJoint(o, spec.jointPrefix + std::to_string(k + 1), parentRef, centre, line.front(), axis,
             spec.jointStiffness, spec.jointDamping);
    parentRef = line.back();
    centre = nextCentre;
    axis = nextAxis;
    joint = next;
  }
  parts.tool = centre;
  o.spacing = minSpacing;
  return parts;
}

void moveToEnd(GeneratedObject& o, const std::vector<int>& particles) {
  const auto n = static_cast<int>(o.size());
  std::vector<int> order;
  std::vector<bool> moved(static_cast<std::size_t>(n), false);
  for (int p : particles) {
    if (p < 0 || p >= n || moved[static_cast<std::size_t>(p)])
      check::fail("moveToEnd", "particles",
                  "'particles': " + std::to_string(p) +
                      " is out of range or listed twice (the object has " + std::to_string(n) +
                      " particles)");
    moved[static_cast<std::size_t>(p)] = true;
  }
  for (int i = 0; i < n; ++i)
    if (!moved[static_cast<std::size_t>(i)]) order.push_back(i);
  order.insert(order.end(), particles.begin(), particles.end());
  std::vector<int> newIndex(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) newIndex[static_cast<std::size_t>(order[k])] = k;
  const auto permute = [&order](auto& values) {
    auto copy = values;
    for (std::size_t k = 0; k < order.size(); ++k)
      values[k] = copy[static_cast<std::size_t>(order[k])];
  };
  permute(o.position);
  permute(o.mass);
  permute(o.radius);
  if (!o.fixed.empty()) permute(o.fixed);
  const auto at = [&newIndex](int i) { return newIndex[static_cast<std::size_t>(i)]; };
  for (auto& s : o.linearSprings) s = {at(s.a), at(s.b), s.restLength, s.stiffness, s.damping};
  for (auto& s : o.torsionSprings) {
    s.a = at(s.a);
    s.b = at(s.b);
    s.c = at(s.c);
  }
  for (auto& s : o.jointSprings) {
    s.a = at(s.a);
    s.b = at(s.b);
    s.c = at(s.c);
    s.d = at(s.d);
  }
}

namespace detail {

void checkRobotLinks(const char* spec, const RobotLinks& links) {
  check::nonNegative(spec, "stiffness", links.stiffness, "N/m");
  check::nonNegative(spec, "damping", links.damping, "N·s/m");
  check::positive(spec, "naturalFrequency", links.naturalFrequency, "rad/s");
}

void resolveRobotLinks(GeneratedObject& o, const RobotLinks& links) {
  resolveSprings(
      o, SpringSettings{links.stiffness, links.damping, 0.0, 0.0, links.naturalFrequency}, 0.0);
}

void setJointDamping(GeneratedObject& o, std::optional<double> damping, double width) {
  // Default: 0.05 √(κ m_min) w², κ the structural LS stiffness.
  const double minMass = *std::min_element(o.mass.begin(), o.mass.end());
  const double value =
      damping.value_or(0.05 * std::sqrt(o.linearSprings[0].stiffness * minMass) * width * width);
  for (auto& s : o.jointSprings) s.damping = value;
}

}  // namespace detail

GeneratedObject makeArm(const ArmSpec& spec) {
  constexpr const char* kSpec = "ArmSpec";
  ChainSpec chain;
  chain.base = spec.base;
  chain.direction = spec.direction;
  chain.links = spec.links;
  const std::size_t n = spec.links.size();
  // One axis for all joints, or one per joint; +z by default.
  if (spec.axes.size() <= 1) {
    chain.axes.assign(n, spec.axes.empty() ? Vec3{0, 0, 1} : spec.axes[0]);
  } else {
    chain.axes = spec.axes;
  }
  chain.mass = spec.mass;
  const double total = std::accumulate(spec.links.begin(), spec.links.end(), 0.0);
  if (spec.width) check::positive(kSpec, "width", *spec.width, "m");
  chain.width = n > 0 ? spec.width.value_or(0.2 * total / static_cast<double>(n)) : 1.0;
  chain.particlesPerLink = spec.particlesPerLink;
  chain.radius = spec.radius;
  chain.jointStiffness = spec.jointStiffness;
  checkChain(kSpec, chain);
  check::nonNegative(kSpec, "jointDamping", spec.jointDamping, "N·m·s/rad");
  detail::checkRobotLinks(kSpec, spec.structure);
  chain.direction = unit(chain.direction);
  for (Vec3& axis : chain.axes) axis = unit(axis);

  GeneratedObject g;
  const ChainParts parts = appendChain(g, chain);
  g.fixed.assign(g.size(), false);
  for (int b : parts.base) g.fixed[static_cast<std::size_t>(b)] = true;
  moveToEnd(g, {parts.tool});
  detail::resolveRobotLinks(g, spec.structure);
  detail::setJointDamping(g, spec.jointDamping, chain.width);
  return g;
}

}  // namespace robophi::build
