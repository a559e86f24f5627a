#pragma once
/// \file
/// Robot generators (docs/robotics.md): `arm` (serial manipulator with n revolute
/// joints), `vehicle` (chassis, suspension, wheels on revolute axles) and `hand`
/// (three fingers of three revolute joints each, like the Salisbury hand). Each
/// is one object whose named joints are placed as "<object>.<joint>". Bodies are
/// small rigid particle sets (complete LS graphs); a revolute joint is two bodies
/// sharing an axis (centre and axis particles) plus a JS (MODEL §1).
///
/// The specs hold what the scene keys of the same names hold (docs/robotics.md),
/// with the same defaults; a key the scene requires has a working default here.
/// Every builder checks its spec first and throws SpecError naming the field.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "robophi/build/objects.h"

namespace robophi::build {

/// A serial chain of revolute joints from a fixed base (the arm, each finger).
struct ChainSpec {
  /// First joint's centre (m) and the chain's initial direction (-, a unit vector).
  Vec3 base{0.0, 0.0, 0.0};
  Vec3 direction{1.0, 0.0, 0.0};
  /// Link lengths (m, > 0), one per joint; axes (-, unit vectors) one per joint,
  /// none parallel to `direction`.
  std::vector<double> links{0.5, 0.4};
  std::vector<Vec3> axes{{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}};
  /// Total mass of the links (kg), > 0, spread in proportion to their lengths.
  double mass = 1.0;
  /// Distance (m, > 0) of the axis and brace particles from the link's line.
  double width = 0.05;
  /// Particles along each link (>= 2), the next joint's centre included.
  int particlesPerLink = 3;
  /// Radius (m, >= 0) of the particles on the line; 0: 0.45 × their spacing.
  double radius = 0.0;
  /// Servo stiffness (N·m/rad, >= 0; 0: passive) and damping (N·m·s/rad, >= 0)
  /// of every joint.
  double jointStiffness = 0.0, jointDamping = 0.0;
  /// Joint names are prefix1..prefixN.
  std::string jointPrefix = "j";
};

/// Local indices of what a chain built.
struct ChainParts {
  std::vector<int> base{};  // the base particles (the arm fixes them)
  int tool = -1;            // the end particle of the last link
};
/// Appends a chain to `object` (positions, masses, radii, LS with stiffness 0 to
/// be resolved, JS and joints); joint values start at π (straight).
ChainParts appendChain(GeneratedObject& object, const ChainSpec& spec);

/// Moves the listed particles to the end of the object, in that order, and
/// renumbers every connector and the fixed flags (tools and tips become "object:-k").
void moveToEnd(GeneratedObject& object, const std::vector<int>& particles);

/// The LS of a robot: one stiffness and damping for every structural link.
struct RobotLinks {
  /// LS stiffness κ (N/m), >= 0; unset: defaultStiffness at `naturalFrequency`.
  std::optional<double> stiffness{};
  /// LS damping μ (N·s/m), >= 0; unset: 0.2 √(κ m_min / 2).
  std::optional<double> damping{};
  /// Natural frequency ω (rad/s), > 0, of the robot's fastest mode when
  /// `stiffness` is unset.
  double naturalFrequency = kDefaultNaturalFrequency;
};

/// Scene type "arm": a serial manipulator fixed at its base.
struct ArmSpec {
  /// First joint's centre (m).
  Vec3 base{0.0, 0.0, 0.0};
  /// Initial direction of the (straight) arm (-), non-zero; normalised.
  Vec3 direction{1.0, 0.0, 0.0};
  /// Link lengths (m), each > 0; one joint per link.
  std::vector<double> links{0.5, 0.4};
  /// Joint axes (-): empty (every axis +z), one axis for every joint, or one per
  /// joint; non-zero, none parallel to `direction` (no roll joints).
  std::vector<Vec3> axes{};
  /// Total mass of the links (kg), > 0.
  double mass = 1.0;
  /// Distance of the axis and brace particles from the links (m), > 0; unset:
  /// 0.2 × the mean link length.
  std::optional<double> width{};
  /// Particles along each link, >= 2.
  int particlesPerLink = 3;
  /// Radius of the particles on the links (m), >= 0; 0: 0.45 × their spacing.
  double radius = 0.0;
  /// Joint servo stiffness (N·m/rad), >= 0; 0: passive.
  double jointStiffness = 0.0;
  /// Joint damping (N·m·s/rad), >= 0; unset: 0.05 √(κ m_min) w².
  std::optional<double> jointDamping{};
  RobotLinks structure{};
};
/// The arm: joints "j1".."jn" (π = straight), base particles fixed, the tool last.
GeneratedObject makeArm(const ArmSpec& spec);

/// Scene type "vehicle": a chassis on four wheels (front left, front right, rear
/// left, rear right) held by suspension springs, on passive revolute axles.
struct VehicleSpec {
  /// Chassis centre (m).
  Vec3 center{0.0, 0.0, 0.12};
  /// Chassis size (m), each side > 0 (a 3×2×2 lattice).
  Vec3 size{0.6, 0.3, 0.1};
  /// Chassis mass (kg), > 0.
  double mass = 8.0;
  /// Wheel outer radius (m), width (m) and mass (kg), each > 0.
  double wheelRadius = 0.12, wheelWidth = 0.06, wheelMass = 0.5;
  /// Particles per wheel rim ring, >= 6.
  int rimParticles = 12;
  /// Distance between the axles (m), > 0; unset: 0.8 × size.x.
  std::optional<double> wheelbase{};
  /// Distance between the left and right wheels (m), > 0; unset:
  /// size.y + wheelWidth + 0.5 wheelRadius.
  std::optional<double> track{};
  /// Suspension spring stiffness (N/m), > 0.
  double suspensionStiffness = 3000.0;
  /// Suspension damping (N·s/m), >= 0; unset: 0.5 √(κ_s m / 8).
  std::optional<double> suspensionDamping{};
  /// Axle damping (N·m·s/rad), >= 0.
  double axleDamping = 0.0;
  /// Wheel motors (MODEL §1.6) on the four axles, so that it drives by traction:
  /// a rate drive of gain `wheelGain` (N·m·s/rad, >= 0; 0: none) towards the wheel
  /// rate `wheelSpeed` (rad/s; positive drives it forward, +x), plus a constant
  /// torque `wheelTorque` (N·m, positive forward), each motor bounded by
  /// `wheelTorqueLimit` (N·m, > 0; unset: none). The axles' joints turn the other
  /// way on the right side (their axes point outward): the builder gives each its sign.
  double wheelSpeed = 0.0, wheelGain = 0.0, wheelTorque = 0.0;
  std::optional<double> wheelTorqueLimit{};
  RobotLinks structure{};
};
/// The vehicle: chassis particles 0..11, joints "axle1".."axle4" (front left,
/// front right, rear left, rear right; each axis points outward, so q̇ > 0 drives
/// the left wheels forward and the right ones backward); nothing fixed.
GeneratedObject makeVehicle(const VehicleSpec& spec);

/// Scene type "hand": a fixed palm disc facing up with three fingers of three
/// revolute joints each, in the Salisbury layout: two fingers side by side (f1,
/// f2 at ±45° about +x) opposing a thumb (f3, on −x). Its particles weigh `mass`.
struct HandSpec {
  /// Palm centre (m).
  Vec3 center{0.0, 0.0, 0.0};
  /// Palm radius (m), > 0.
  double palmRadius = 0.06;
  /// Finger link lengths [proximal, middle, distal] (m), each > 0.
  std::array<double, 3> links{0.05, 0.04, 0.03};
  /// Total mass (kg), > 0: a quarter in the palm, the rest in the fingers.
  double mass = 0.3;
  /// Finger width (m), > 0; unset: 0.15 × the mean link length.
  std::optional<double> width{};
  /// Joint servo stiffness (N·m/rad), >= 0; 0: passive.
  double jointStiffness = 0.0;
  /// Joint damping (N·m·s/rad), >= 0; unset: 0.05 √(κ m_min) w².
  std::optional<double> jointDamping{};
  /// Inward lean of the fingers from the vertical (rad), finite.
  double spread = 0.0;
  RobotLinks structure{};
};
/// The hand: joints "f1.j1".."f3.j3", palm and finger bases fixed, the three
/// finger tips last (local -3, -2, -1).
GeneratedObject makeHand(const HandSpec& spec);

}  // namespace robophi::build
