// Robot generators: arm, vehicle, hand (docs/robotics.md). Bodies are small
// rigid particle sets (complete LS graphs); revolute joints are two bodies
// sharing an axis (centre and axis particles) plus a JS (MODEL §1).
#include "robotics/robot_builders.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "robophi/connector_forces.h"

namespace robophi::robotics {

namespace {

using io::Bound;
using io::GeneratedObject;
using io::ObjectReader;

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
  o.joints.push_back(
      {name, JointKind::kRevolute, static_cast<std::int32_t>(o.jointSprings.size()) - 1, -1});
}

// Common keys: structural stiffness and damping of the LS (defaults as generators).
io::SpringSettings readStructure(ObjectReader& r) {
  io::SpringSettings s;
  s.stiffness = r.number("stiffness", Bound::kNonNegative, "N/m");
  s.damping = r.number("damping", Bound::kNonNegative, "N·s/m");
  s.bendStiffness = 0.0;
  s.bendDamping = 0.0;
  return s;
}

bool readArm(ObjectReader& r, io::SceneObject& object, double dt) {
  ChainSpec spec;
  const auto base = r.vec3("base", "m", true);
  const auto direction = r.vec3("direction", "-");
  const nlohmann::json* links = r.member("links");
  const nlohmann::json* axes = r.member("axes");
  const auto mass = r.number("mass", Bound::kPositive, "kg", true);
  const auto width = r.number("width", Bound::kPositive, "m");
  const auto perLink = r.integer("particlesPerLink", 2);
  const auto radius = r.number("radius", Bound::kPositive, "m");
  spec.jointStiffness = r.numberOr("jointStiffness", 0.0, Bound::kNonNegative, "N·m/rad");
  const auto jointDamping = r.number("jointDamping", Bound::kNonNegative, "N·m·s/rad");
  const auto springs = readStructure(r);
  bool ok = base && mass && (!r.member("particlesPerLink") || perLink);
  if (links == nullptr) {
    r.missing("links", "an array of link lengths (m)");
    ok = false;
  } else if (!links->is_array() || links->empty()) {
    r.sink().error(r.memberPointer("links"), "'links': expected a non-empty array of lengths (m)");
    ok = false;
  } else {
    for (std::size_t i = 0; i < links->size(); ++i) {
      const auto v =
          io::checkNumber(r.sink(), (*links)[i], fmt::format("{}/{}", r.memberPointer("links"), i),
                          "links", Bound::kPositive, "m");
      ok = ok && v.has_value();
      spec.links.push_back(v.value_or(1.0));
    }
  }
  spec.direction = direction.value_or(Vec3{1, 0, 0});
  if (!(norm(spec.direction) > 0.0)) {
    r.sink().error(r.memberPointer("direction"), "'direction' must be a non-zero vector");
    return false;
  }
  spec.direction = unit(spec.direction);
  const std::size_t n = spec.links.size();
  spec.axes.assign(n, Vec3{0, 0, 1});
  if (axes != nullptr) {
    // One axis for all joints, or one per joint.
    const bool single = axes->is_array() && axes->size() == 3 && (*axes)[0].is_number();
    if (!axes->is_array() || (!single && axes->size() != n)) {
      r.sink().error(r.memberPointer("axes"),
                     fmt::format("'axes': expected one axis [x, y, z] or {} of them", n));
      return false;
    }
    for (std::size_t i = 0; i < n && ok; ++i) {
      const nlohmann::json& v = single ? *axes : (*axes)[i];
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
          !v[2].is_number()) {
        r.sink().error(r.memberPointer("axes"), "'axes': each axis must be [x, y, z]");
        return false;
      }
      spec.axes[i] = Vec3{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
    }
  }
  for (std::size_t i = 0; i < n && ok; ++i) {
    if (!(norm(spec.axes[i]) > 0.0) || norm(cross(unit(spec.axes[i]), spec.direction)) < 1e-3) {
      r.sink().error(r.memberPointer("axes"),
                     fmt::format("'axes': joint {} axis is zero or parallel to 'direction' "
                                 "(a roll joint is not supported)",
                                 i + 1));
      return false;
    }
    spec.axes[i] = unit(spec.axes[i]);
  }
  if (!ok) return false;
  const double total = std::accumulate(spec.links.begin(), spec.links.end(), 0.0);
  spec.mass = *mass;
  spec.width = width.value_or(0.2 * total / static_cast<double>(n));
  spec.particlesPerLink = perLink.value_or(3);
  spec.radius = radius.value_or(0.0);
  spec.base = *base;
  GeneratedObject& g = object.geometry;
  const ChainParts parts = appendChain(g, spec);
  object.fixed.assign(g.size(), false);
  for (int b : parts.base) object.fixed[static_cast<std::size_t>(b)] = true;
  moveToEnd(g, {parts.tool}, &object.fixed);
  io::resolveSprings(g, springs, dt, 0.0);
  const double minMass = *std::min_element(g.mass.begin(), g.mass.end());
  const double jd = jointDamping.value_or(0.05 * std::sqrt(g.linearSprings[0].stiffness * minMass) *
                                          spec.width * spec.width);
  for (auto& s : g.jointSprings) s.damping = jd;
  return true;
}

}  // namespace

int addParticle(GeneratedObject& o, const Vec3& p, double mass, double radius) {
  o.position.push_back(p);
  o.mass.push_back(mass);
  o.radius.push_back(radius);
  return static_cast<int>(o.position.size()) - 1;
}

int addLink(GeneratedObject& o, int a, int b) {
  o.linearSprings.push_back({a, b, norm(o.position[a] - o.position[b]), 0.0, 0.0});
  return static_cast<int>(o.linearSprings.size()) - 1;
}

ChainParts appendChain(GeneratedObject& o, const ChainSpec& spec) {
  ChainParts parts;
  const std::size_t n = spec.links.size();
  const Vec3 e = spec.direction;
  const int m = std::max(spec.particlesPerLink, 2);
  const double total = std::accumulate(spec.links.begin(), spec.links.end(), 0.0);
  const double w = spec.width;
  double minSpacing = spec.links[0] / m;
  for (double l : spec.links) minSpacing = std::min(minSpacing, l / m);
  const double r = spec.radius > 0.0 ? spec.radius : 0.45 * minSpacing;
  const double small = std::min(r, 0.3 * w);
  // Base: joint 1 centre, axis particle, and a reference behind (all fixed).
  const double baseMass = spec.mass / (static_cast<double>(n) * (m + 3));
  int centre = addParticle(o, spec.base, baseMass, r);
  int axis = addParticle(o, spec.base + spec.axes[0] * w, baseMass, small);
  int parentRef = addParticle(o, spec.base - e * w, baseMass, small);
  parts.base = {centre, axis, parentRef};
  Vec3 joint = spec.base;
  for (std::size_t k = 0; k < n; ++k) {
    const double length = spec.links[k];
    const double linkMass = spec.mass * length / total;
    const double each = linkMass / static_cast<double>(m + 3);
    const Vec3 ax = spec.axes[k];
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
      nextAxis = addParticle(o, next + spec.axes[k + 1] * w, each, small);
    } else {
      // The last link's third brace keeps the tool's body 3-D.
      nextAxis = addParticle(o, next - v1 * w, each, small);
    }
    body.insert(body.end(), line.begin(), line.end());
    body.push_back(nextCentre);
    body.push_back(nextAxis);
    rigidBody(o, body, {centre, axis});
    // MODEL §1 JS: a on the parent body, b on this link; straight is π.
    addJoint(o, fmt::format("{}{}", spec.jointPrefix, k + 1), parentRef, centre, line.front(), axis,
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

void moveToEnd(GeneratedObject& o, const std::vector<int>& particles, std::vector<bool>* fixed) {
  const auto n = static_cast<int>(o.size());
  std::vector<int> order;
  std::vector<bool> moved(static_cast<std::size_t>(n), false);
  for (int p : particles) moved[static_cast<std::size_t>(p)] = true;
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
  if (fixed != nullptr) permute(*fixed);
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

bool readVehicle(ObjectReader& r, io::SceneObject& object, double dt);
bool readHand(ObjectReader& r, io::SceneObject& object, double dt);

bool isRobotKind(const std::string& kind) {
  return kind == "arm" || kind == "vehicle" || kind == "hand";
}

bool readRobot(ObjectReader& r, io::SceneObject& object, double dt) {
  if (object.kind == "arm") return readArm(r, object, dt);
  if (object.kind == "vehicle") return readVehicle(r, object, dt);
  return readHand(r, object, dt);
}

}  // namespace robophi::robotics
