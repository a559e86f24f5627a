// The vehicle (chassis, suspension, wheels on revolute axles) and the
// three-fingered hand (docs/robotics.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "robophi/connector_forces.h"
#include "robotics/robot_builders.h"

namespace robophi::robotics {

namespace {

using io::Bound;
using io::GeneratedObject;
using io::ObjectReader;

// Appends `part` (local indices) to `o`; returns the offset of its particles.
int append(GeneratedObject& o, const GeneratedObject& part) {
  const auto offset = static_cast<int>(o.size());
  o.position.insert(o.position.end(), part.position.begin(), part.position.end());
  o.mass.insert(o.mass.end(), part.mass.begin(), part.mass.end());
  o.radius.insert(o.radius.end(), part.radius.begin(), part.radius.end());
  for (LinearSpring s : part.linearSprings) {
    s.a += offset;
    s.b += offset;
    o.linearSprings.push_back(s);
  }
  return offset;
}

}  // namespace

bool readVehicle(ObjectReader& r, io::SceneObject& object, double dt) {
  const auto center = r.vec3("center", "m", true);
  const auto size = r.vec3("size", "m", true);
  const auto chassisMass = r.number("mass", Bound::kPositive, "kg", true);
  const auto wheelRadius = r.number("wheelRadius", Bound::kPositive, "m", true);
  const auto wheelWidth = r.number("wheelWidth", Bound::kPositive, "m", true);
  const auto wheelMass = r.number("wheelMass", Bound::kPositive, "kg", true);
  const auto rim = r.integer("rimParticles", 6);
  const auto wheelbase = r.number("wheelbase", Bound::kPositive, "m");
  const auto track = r.number("track", Bound::kPositive, "m");
  const auto suspension = r.number("suspensionStiffness", Bound::kPositive, "N/m", true);
  const auto suspensionDamping = r.number("suspensionDamping", Bound::kNonNegative, "N·s/m");
  const double axleDamping = r.numberOr("axleDamping", 0.0, Bound::kNonNegative, "N·m·s/rad");
  const io::SpringSettings springs{r.number("stiffness", Bound::kNonNegative, "N/m"),
                                   r.number("damping", Bound::kNonNegative, "N·s/m"), 0.0, 0.0};
  if (!center || !size || !chassisMass || !wheelRadius || !wheelWidth || !wheelMass ||
      !suspension || (r.member("rimParticles") && !rim))
    return false;
  if (!(size->x > 0.0 && size->y > 0.0 && size->z > 0.0)) {
    r.sink().error(r.memberPointer("size"), "'size' must be > 0 m in each direction");
    return false;
  }
  const double R = *wheelRadius, W = *wheelWidth;
  const double base = wheelbase.value_or(0.8 * size->x);
  const double trackWidth = track.value_or(size->y + W + 0.5 * R);
  GeneratedObject& g = object.geometry;
  // Chassis: a rigid 3×2×2 lattice.
  const GeneratedObject chassis = io::makeBox({*center, *size, {3, 2, 2}, *chassisMass, 0.0});
  append(g, chassis);
  const int chassisCount = static_cast<int>(g.size());
  std::vector<int> suspensionSprings;
  // Wheels: front left, front right, rear left, rear right.
  const double xs[2] = {0.5 * base, -0.5 * base};
  const double ys[2] = {0.5 * trackWidth, -0.5 * trackWidth};
  const int n = rim.value_or(12);
  const double mountMass = 0.02 * *chassisMass;
  const double mountRadius = 0.1 * R;
  int wheelIndex = 0;
  for (double x : xs) {
    for (double y : ys) {
      ++wheelIndex;
      const Vec3 wheelCenter = *center + Vec3{x, y, 0.0};
      const int offset = append(g, io::makeWheel({wheelCenter, R, W, {0, 1, 0}, n, *wheelMass}));
      const double side = y > 0.0 ? 1.0 : -1.0;
      int hubs[2] = {offset + 2 * n, offset + 2 * n + 1};
      if (side * (g.position[hubs[0]].y - g.position[hubs[1]].y) > 0.0) std::swap(hubs[0], hubs[1]);
      // Mounts, rigid with the chassis: ahead/behind (toward the middle), inward on
      // the axle line, and above each hub. Two stiff links fix a hub in x and y;
      // the soft link above is the suspension spring (MODEL §5: the vehicle adapts).
      const double towardMiddle = x > 0.0 ? -1.0 : 1.0;
      const int inward = addParticle(g, g.position[hubs[0]] - Vec3{0.0, side * 0.6 * W, 0.0},
                                     mountMass, mountRadius);
      std::vector<int> mounts = {inward};
      for (int hub : hubs) {
        const int ahead = addParticle(g, g.position[hub] + Vec3{towardMiddle * 1.5 * R, 0.0, 0.0},
                                      mountMass, mountRadius);
        const int above =
            addParticle(g, g.position[hub] + Vec3{0.0, 0.0, 1.5 * R}, mountMass, mountRadius);
        mounts.push_back(ahead);
        mounts.push_back(above);
        addLink(g, hub, ahead);
        addLink(g, hub, inward);
        suspensionSprings.push_back(addLink(g, hub, above));
      }
      for (int mount : mounts)
        for (int c = 0; c < chassisCount; ++c) addLink(g, mount, c);
      // MODEL §1 JS: the axle, a passive revolute joint (a: a mount, b: a rim particle).
      const int a = mounts[1];
      const auto& p = g.position;
      g.jointSprings.push_back({a, hubs[0], offset, hubs[1],
                                jointAngle(p[a], p[hubs[0]], p[offset], p[hubs[1]]), 0.0,
                                axleDamping});
      g.joints.push_back({fmt::format("axle{}", wheelIndex), JointKind::kRevolute,
                          static_cast<std::int32_t>(g.jointSprings.size()) - 1, -1});
    }
  }
  g.spacing = size->x / 3.0;
  io::resolveSprings(g, springs, dt, 0.0);
  const double damping =
      suspensionDamping.value_or(0.5 * std::sqrt(*suspension * (*chassisMass / 8.0)));
  for (int s : suspensionSprings) {
    g.linearSprings[static_cast<std::size_t>(s)].stiffness = *suspension;
    g.linearSprings[static_cast<std::size_t>(s)].damping = damping;
  }
  object.fixed.assign(g.size(), false);
  return true;
}

bool readHand(ObjectReader& r, io::SceneObject& object, double dt) {
  const auto center = r.vec3("center", "m", true);
  const auto palmRadius = r.number("palmRadius", Bound::kPositive, "m", true);
  const auto links = r.numbers("links", 3, "[proximal, middle, distal] (m)", true);
  const auto mass = r.number("mass", Bound::kPositive, "kg", true);
  const auto width = r.number("width", Bound::kPositive, "m");
  const double jointStiffness = r.numberOr("jointStiffness", 0.0, Bound::kNonNegative, "N·m/rad");
  const auto jointDamping = r.number("jointDamping", Bound::kNonNegative, "N·m·s/rad");
  const auto spread = r.number("spread", Bound::kAny, "rad");
  const io::SpringSettings springs{r.number("stiffness", Bound::kNonNegative, "N/m"),
                                   r.number("damping", Bound::kNonNegative, "N·s/m"), 0.0, 0.0};
  if (!center || !palmRadius || !links || !mass) return false;
  GeneratedObject& g = object.geometry;
  const double rho = *palmRadius;
  const double fingerLength = (*links)[0] + (*links)[1] + (*links)[2];
  const double w = width.value_or(0.15 * fingerLength / 3.0);
  // Palm: a fixed disc of particles in the plane z = center.z, facing up.
  const double pitch = 0.5 * rho;
  const double palmParticleRadius = 0.5 * pitch;
  std::vector<int> base;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) {
      const Vec3 offset{i * pitch, j * pitch, 0.0};
      if (norm(offset) <= rho + 1e-9)
        base.push_back(addParticle(g, *center + offset, *mass / 10.0, palmParticleRadius));
    }
  // Fingers: joint 1 swings the finger sideways (axis radial), joints 2 and 3 flex
  // it toward the middle (axis tangential): three revolute joints per finger.
  std::vector<int> tips;
  for (int f = 0; f < 3; ++f) {
    const double phi = M_PI / 2.0 + 2.0 * M_PI * f / 3.0;
    const Vec3 radial{std::cos(phi), std::sin(phi), 0.0};
    const Vec3 tangential{-std::sin(phi), std::cos(phi), 0.0};
    ChainSpec finger;
    finger.base = *center + radial * (rho + w) + Vec3{0.0, 0.0, palmParticleRadius};
    // Fingers lean inward by `spread` (rad) from the vertical.
    const double lean = spread.value_or(0.0);
    finger.direction = Vec3{0, 0, 1} * std::cos(lean) - radial * std::sin(lean);
    finger.links = {(*links)[0], (*links)[1], (*links)[2]};
    finger.axes = {radial, tangential, tangential};
    finger.mass = *mass / 3.0;
    finger.width = w;
    finger.particlesPerLink = 2;
    finger.jointStiffness = jointStiffness;
    finger.jointPrefix = fmt::format("f{}.j", f + 1);
    const ChainParts parts = appendChain(g, finger);
    base.insert(base.end(), parts.base.begin(), parts.base.end());
    tips.push_back(parts.tool);
  }
  object.fixed.assign(g.size(), false);
  for (int b : base) object.fixed[static_cast<std::size_t>(b)] = true;
  moveToEnd(g, tips, &object.fixed);
  io::resolveSprings(g, springs, dt, 0.0);
  const double minMass = *std::min_element(g.mass.begin(), g.mass.end());
  const double jd =
      jointDamping.value_or(0.05 * std::sqrt(g.linearSprings[0].stiffness * minMass) * w * w);
  for (auto& s : g.jointSprings) s.damping = jd;
  return true;
}

}  // namespace robophi::robotics
