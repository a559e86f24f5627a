#pragma once
// Robot generators for scene files (docs/robotics.md): `arm` (serial manipulator
// with n revolute joints), `vehicle` (chassis, suspension, wheels on revolute
// axles) and `hand` (three fingers of three revolute joints each, like the
// Salisbury hand). Each is one scene object whose named joints are placed as
// "<object>.<joint>". Wired into the loader by one line in io/scene_objects.cpp.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "io/generators.h"
#include "io/scene_objects.h"
#include "scene/scene_fields.h"

namespace robophi::robotics {

/// A serial chain of revolute joints from a fixed base (the arm, each finger).
struct ChainSpec {
  /// First joint's centre (m) and the chain's initial direction (-, straight).
  Vec3 base{0.0, 0.0, 0.0};
  Vec3 direction{1.0, 0.0, 0.0};
  /// Link lengths (m), one per joint; axes (unit, -) one per joint, none parallel
  /// to `direction`.
  std::vector<double> links;
  std::vector<Vec3> axes;
  /// Total mass of the links (kg), spread in proportion to their lengths.
  double mass = 1.0;
  /// Distance (m) of the axis and brace particles from the link's line.
  double width = 0.05;
  /// Particles along each link (>= 2), the next joint's centre included.
  int particlesPerLink = 3;
  /// Radius (m) of the particles on the line; 0: 0.45 × their spacing.
  double radius = 0.0;
  /// Servo stiffness (N·m/rad; 0: passive) and damping of every joint.
  double jointStiffness = 0.0, jointDamping = 0.0;
  /// Joint names are prefix1..prefixN.
  std::string jointPrefix = "j";
};

/// Local indices of what a chain built.
struct ChainParts {
  std::vector<int> base;  // fixed base particles
  int tool = -1;          // the end particle of the last link
};
/// Appends a chain to `object` (positions, masses, radii, LS with stiffness 0 to
/// be resolved, JS and joints); joint values start at π (straight).
ChainParts appendChain(io::GeneratedObject& object, const ChainSpec& spec);

/// Appends a particle to `object`; returns its local index.
int addParticle(io::GeneratedObject& object, const Vec3& position, double mass, double radius);
/// Appends an LS between local particles a and b at rest at their distance, its
/// stiffness and damping (0) to be resolved; returns its index.
int addLink(io::GeneratedObject& object, int a, int b);

/// Moves the listed particles to the end of the object, in that order, and
/// renumbers every connector (tools and tips become "object:-k").
void moveToEnd(io::GeneratedObject& object, const std::vector<int>& particles,
               std::vector<bool>* fixed);

/// Sets a box lattice's LS from elastic moduli E (Pa) and G (Pa, default 0.4 E)
/// so that its traction, flexion and torsion stiffness match E·A/L, 3·E·I/L³ and
/// G·J/L (docs/robotics.md#bar-calibration-experiment-1). Needs cubic cells. Returns false
/// (reported) when the lattice cannot be calibrated.
bool calibrateLattice(io::ObjectReader& r, io::GeneratedObject& box, const Vec3& size,
                      const std::array<int, 3>& cells, double youngModulus,
                      std::optional<double> shearModulus);

bool isRobotKind(const std::string& kind);
/// Reads an arm, vehicle or hand entry into `object` (geometry and fixed
/// particles). Returns false when a parameter is missing or bad (reported).
bool readRobot(io::ObjectReader& r, io::SceneObject& object, double dt);

}  // namespace robophi::robotics
