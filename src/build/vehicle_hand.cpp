// The vehicle (chassis, suspension, wheels on revolute axles) and the
// three-fingered hand (docs/robotics.md).
#include <algorithm>
#include <cmath>
#include <string>

#include "build/checks.h"
#include "build/robot_parts.h"
#include "robophi/build/robots.h"
#include "robophi/connector_forces.h"

namespace robophi::build {

namespace {

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
  for (RimRing rim : part.rims) {
    rim.first += offset;
    if (rim.hub != kNoParticle) rim.hub += offset;
    if (rim.axisParticle != kNoParticle) rim.axisParticle += offset;
    o.rims.push_back(rim);
  }
  return offset;
}

void checkVehicle(const VehicleSpec& spec) {
  constexpr const char* kSpec = "VehicleSpec";
  check::finite(kSpec, "center", spec.center, "m");
  check::positiveEach(kSpec, "size", spec.size, "m");
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::positive(kSpec, "wheelRadius", spec.wheelRadius, "m");
  check::positive(kSpec, "wheelWidth", spec.wheelWidth, "m");
  check::positive(kSpec, "wheelMass", spec.wheelMass, "kg");
  check::atLeast(kSpec, "rimParticles", spec.rimParticles, 6);
  // Four wheels (makeWheel: 2n + 2 particles, 9n + 1 LS) on a chassis, mounts and
  // suspension of a few hundred particles and LS at most.
  check::fitsBudget(kSpec, "rimParticles", "'rimParticles' " + std::to_string(spec.rimParticles),
                    4.0 * (2.0 * spec.rimParticles + 2.0) + 100.0,
                    4.0 * (9.0 * spec.rimParticles + 1.0) + 1000.0);
  if (spec.wheelbase) check::positive(kSpec, "wheelbase", *spec.wheelbase, "m");
  if (spec.track) check::positive(kSpec, "track", *spec.track, "m");
  check::positive(kSpec, "suspensionStiffness", spec.suspensionStiffness, "N/m");
  check::nonNegative(kSpec, "suspensionDamping", spec.suspensionDamping, "N·s/m");
  check::nonNegative(kSpec, "axleDamping", spec.axleDamping, "N·m·s/rad");
  check::finite(kSpec, "wheelSpeed", spec.wheelSpeed, "rad/s");
  check::nonNegative(kSpec, "wheelGain", spec.wheelGain, "N·m·s/rad");
  check::finite(kSpec, "wheelTorque", spec.wheelTorque, "N·m");
  if (spec.wheelTorqueLimit)
    check::positive(kSpec, "wheelTorqueLimit", *spec.wheelTorqueLimit, "N·m");
  detail::checkRobotLinks(kSpec, spec.structure);
}

void checkHand(const HandSpec& spec) {
  constexpr const char* kSpec = "HandSpec";
  check::finite(kSpec, "center", spec.center, "m");
  check::positive(kSpec, "palmRadius", spec.palmRadius, "m");
  for (double length : spec.links) check::positive(kSpec, "links", length, "m");
  check::positive(kSpec, "mass", spec.mass, "kg");
  if (spec.width) check::positive(kSpec, "width", *spec.width, "m");
  check::nonNegative(kSpec, "jointStiffness", spec.jointStiffness, "N·m/rad");
  check::nonNegative(kSpec, "jointDamping", spec.jointDamping, "N·m·s/rad");
  check::finite(kSpec, "spread", spec.spread, "rad");
  detail::checkRobotLinks(kSpec, spec.structure);
}

}  // namespace

GeneratedObject makeVehicle(const VehicleSpec& spec) {
  checkVehicle(spec);
  const double R = spec.wheelRadius, W = spec.wheelWidth;
  const double base = spec.wheelbase.value_or(0.8 * spec.size.x);
  const double trackWidth = spec.track.value_or(spec.size.y + W + 0.5 * R);
  GeneratedObject g;
  // Chassis: a rigid 3×2×2 lattice.
  const GeneratedObject chassis = makeBox({spec.center, spec.size, {3, 2, 2}, spec.mass, 0.0});
  append(g, chassis);
  const int chassisCount = static_cast<int>(g.size());
  std::vector<int> suspensionSprings;
  // Wheels: front left, front right, rear left, rear right.
  const double xs[2] = {0.5 * base, -0.5 * base};
  const double ys[2] = {0.5 * trackWidth, -0.5 * trackWidth};
  const int n = spec.rimParticles;
  const double mountMass = 0.02 * spec.mass;
  const double mountRadius = 0.1 * R;
  // Every length of the suspension scales with the wheel's radius, none with its
  // width: a wheel stands on its hubs, and the chassis leans on the wheels' camber
  // stiffness (the vehicle sways sideways on them when it is short, the wheels
  // tilting under the chassis: the weight on a wheel, N, tilts it further by
  // N R per radian). That stiffness is about k s² / 2 for a hub span s held by
  // links of stiffness k, so the hubs stand at least R/2 apart (beyond a narrow
  // tyre, as a bicycle's hub flanges; the mounts beside them, 0.2 R across, never
  // touch), and each wheel's hubs hang from a knuckle held by stiff arms (below).
  const double hubSpan = std::max(0.5 * W, 0.5 * R);
  // The lateral arms (hub and knuckle to their inward mounts): the length of a
  // wheel, not of its width; the chassis sags by millimetres whatever the width,
  // and an arm of millimetres would turn steeply with that sag and carry weight.
  const double lateralArm = 0.3 * R;
  const double trailingArm = 1.5 * R;
  // The knuckle stands this high above the axle, beside the tyre's inner face.
  const double knuckleHeight = 0.5 * R;
  struct Corner {
    int hubs[2];
    double side, towardMiddle;
    Vec3 wheelCenter;
  };
  std::vector<Corner> corners;
  int wheelIndex = 0;
  for (double x : xs) {
    for (double y : ys) {
      ++wheelIndex;
      const Vec3 wheelCenter = spec.center + Vec3{x, y, 0.0};
      const int offset =
          append(g, makeWheel({wheelCenter, R, W, {0, 1, 0}, n, spec.wheelMass, hubSpan}));
      const double side = y > 0.0 ? 1.0 : -1.0;
      int hubs[2] = {offset + 2 * n, offset + 2 * n + 1};
      if (side * (g.position[hubs[0]].y - g.position[hubs[1]].y) > 0.0) std::swap(hubs[0], hubs[1]);
      // Mounts, rigid with the chassis: ahead/behind (toward the middle), inward on
      // the axle line, and above each hub. Two stiff links fix a hub in x and y
      // (the lower trailing and lateral arms); the soft link above is the
      // suspension spring (MODEL §6.3: the vehicle adapts).
      const double towardMiddle = x > 0.0 ? -1.0 : 1.0;
      corners.push_back({{hubs[0], hubs[1]}, side, towardMiddle, wheelCenter});
      const int inward = addParticle(g, g.position[hubs[0]] - Vec3{0.0, side * lateralArm, 0.0},
                                     mountMass, mountRadius);
      std::vector<int> mounts = {inward};
      for (int hub : hubs) {
        const int ahead =
            addParticle(g, g.position[hub] + Vec3{towardMiddle * trailingArm, 0.0, 0.0},
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
      const double angle = jointAngle(p[a], p[hubs[0]], p[offset], p[hubs[1]]);
      g.jointSprings.push_back({a, hubs[0], offset, hubs[1], angle, 0.0, spec.axleDamping});
      g.joints.push_back({"axle" + std::to_string(wheelIndex), JointKind::kRevolute,
                          static_cast<std::int32_t>(g.jointSprings.size()) - 1, -1, angle});
      // MODEL §1.6 wheel motor: the axle's axis points outward, so forward is +q on
      // the left (y > 0) and −q on the right.
      // The motor acts through every rim particle (Joint::motorParticles), not
      // the JS's one alone: one light particle cannot carry a stiff rate drive.
      for (int k = 1; k < 2 * n; ++k) g.joints.back().motorParticles.push_back(offset + k);
      JointDrive& motor = g.joints.back().drive;
      motor.rateGain = spec.wheelGain;
      motor.targetRate = spec.wheelGain > 0.0 ? side * spec.wheelSpeed : 0.0;
      motor.effort = side * spec.wheelTorque;
      if (spec.wheelTorqueLimit) motor.effortLimit = *spec.wheelTorqueLimit;
    }
  }
  // Knuckles (after the wheels: the layout above stays chassis 0..11, then 2n + 7
  // particles a wheel). A knuckle K above the axle beside the tyre forms a
  // triangle with the two hubs; an upper lateral arm (to J) and an upper trailing
  // arm (to A) parallel to the hub's lower ones and as long make parallelograms,
  // so that the wheel travels up and down on its suspension springs alone while
  // its camber (K sideways) is held by a stiff arm at a lever of R/2.
  for (const Corner& corner : corners) {
    const Vec3 outward{0.0, corner.side, 0.0};
    const Vec3 knuckle = corner.wheelCenter - outward * (0.5 * W + 1.5 * mountRadius) +
                         Vec3{0.0, 0.0, knuckleHeight};
    const int k = addParticle(g, knuckle, mountMass, mountRadius);
    const int lateral = addParticle(g, knuckle - outward * lateralArm, mountMass, mountRadius);
    const int trailing = addParticle(
        g, knuckle + Vec3{corner.towardMiddle * trailingArm, 0.0, 0.0}, mountMass, mountRadius);
    for (int hub : corner.hubs) addLink(g, k, hub);
    addLink(g, k, lateral);
    addLink(g, k, trailing);
    for (int mount : {lateral, trailing})
      for (int c = 0; c < chassisCount; ++c) addLink(g, mount, c);
  }
  g.spacing = spec.size.x / 3.0;
  detail::resolveRobotLinks(g, spec.structure);
  const double damping = spec.suspensionDamping.value_or(
      0.5 * std::sqrt(spec.suspensionStiffness * (spec.mass / 8.0)));
  for (int s : suspensionSprings) {
    g.linearSprings[static_cast<std::size_t>(s)].stiffness = spec.suspensionStiffness;
    g.linearSprings[static_cast<std::size_t>(s)].damping = damping;
  }
  g.fixed.assign(g.size(), false);
  return g;
}

GeneratedObject makeHand(const HandSpec& spec) {
  checkHand(spec);
  GeneratedObject g;
  const double rho = spec.palmRadius;
  const double fingerLength = spec.links[0] + spec.links[1] + spec.links[2];
  const double w = spec.width.value_or(0.15 * fingerLength / 3.0);
  // Palm: a fixed disc of particles in the plane z = center.z, facing up.
  const double pitch = 0.5 * rho;
  const double palmParticleRadius = 0.5 * pitch;
  std::vector<int> base;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) {
      const Vec3 offset{i * pitch, j * pitch, 0.0};
      if (norm(offset) <= rho + 1e-9)
        base.push_back(addParticle(g, spec.center + offset, spec.mass / 10.0, palmParticleRadius));
    }
  const std::size_t palmCount = g.size();
  // Fingers in the Salisbury layout: two fingers side by side (f1, f2, at ±45°
  // about +x) opposing a thumb (f3, at 180°). Joint 1 swings the finger sideways
  // (axis radial), joints 2 and 3 flex it toward the middle (axis tangential):
  // three revolute joints per finger.
  std::vector<int> tips;
  const double angles[3] = {M_PI / 4.0, -M_PI / 4.0, M_PI};
  for (int f = 0; f < 3; ++f) {
    const double phi = angles[f];
    const Vec3 radial{std::cos(phi), std::sin(phi), 0.0};
    const Vec3 tangential{-std::sin(phi), std::cos(phi), 0.0};
    ChainSpec finger;
    finger.base = spec.center + radial * (rho + w) + Vec3{0.0, 0.0, palmParticleRadius};
    // Fingers lean inward by `spread` (rad) from the vertical.
    finger.direction = Vec3{0, 0, 1} * std::cos(spec.spread) - radial * std::sin(spec.spread);
    finger.links = {spec.links[0], spec.links[1], spec.links[2]};
    finger.axes = {radial, tangential, tangential};
    finger.mass = spec.mass / 3.0;
    finger.width = w;
    finger.particlesPerLink = 2;
    finger.jointStiffness = spec.jointStiffness;
    finger.jointPrefix = "f" + std::to_string(f + 1) + ".j";
    const ChainParts parts = appendChain(g, finger);
    base.insert(base.end(), parts.base.begin(), parts.base.end());
    tips.push_back(parts.tool);
  }
  g.fixed.assign(g.size(), false);
  for (int b : base) g.fixed[static_cast<std::size_t>(b)] = true;
  // The hand weighs its declared mass: the palm a quarter, the fingers the rest
  // (their fixed base particles included), each part's particles in proportion.
  double palm = 0.0, total = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    total += g.mass[i];
    if (i < palmCount) palm += g.mass[i];
  }
  for (std::size_t i = 0; i < g.size(); ++i)
    g.mass[i] *= i < palmCount ? 0.25 * spec.mass / palm : 0.75 * spec.mass / (total - palm);
  moveToEnd(g, tips);
  detail::resolveRobotLinks(g, spec.structure);
  detail::setJointDamping(g, spec.jointDamping, w);
  return g;
}

}  // namespace robophi::build
