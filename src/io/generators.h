#pragma once
// Object generators (MODEL §1: an object is a set of particles that respects
// the reference object's mass, centre of mass and volume, tied by connectors).
// Each generator returns the object in local particle indices; the scene
// loader places it in the model. Connectors start at rest: every rest length
// and rest angle is the initial one, so the object starts with zero spring
// energy. Lattice particles have equal masses and sit at the centres of the
// cells, so that spheres of half a cell tile the object's size exactly.

#include <array>
#include <optional>
#include <vector>

#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi::io {

/// An object in local indices (0..size()-1).
struct GeneratedObject {
  std::vector<Vec3> position;                 // (n) m
  std::vector<double> mass;                   // (n) kg
  std::vector<double> radius;                 // (n) m
  std::vector<LinearSpring> linearSprings;    // local indices
  std::vector<TorsionSpring> torsionSprings;  // local indices; stiffness from bend*
  /// The typical distance between neighbours (m): sets default bend stiffness.
  double spacing = 0.0;
  /// Robots (src/robotics/): JS in local indices and their named joints, whose
  /// Joint::connector indexes jointSprings; placed with the name "<object>.<name>".
  std::vector<JointSpring> jointSprings;
  std::vector<Joint> joints;

  std::size_t size() const { return position.size(); }
};

/// The connector parameters of a generated object. Unset values get defaults
/// from the particle masses and the scene's step δ (see resolveSprings).
struct SpringSettings {
  /// LS stiffness κ (N/m).
  std::optional<double> stiffness;
  /// LS damping μ (N·s/m).
  std::optional<double> damping;
  /// TS stiffness along lattice lines (N·m/rad); 0 means no TS.
  std::optional<double> bendStiffness;
  /// TS damping (N·m·s/rad).
  std::optional<double> bendDamping;
};

/// Rope (or chain): `particles` particles from start to end inclusive, LS
/// between neighbours, TS at 180° on consecutive triples when bendStiffness > 0.
struct RopeSpec {
  Vec3 start, end;  // m
  int particles = 10;
  double mass = 1.0;  // kg, total
  /// Particle radius (m); 0: half the spacing.
  double radius = 0.0;
};
GeneratedObject makeRope(const RopeSpec& spec);

/// Box (bar, cube): a cells[0]×cells[1]×cells[2] lattice of equal particles
/// filling `size` around `center`, LS to axis, face-diagonal and body-diagonal
/// neighbours, TS along lattice lines.
struct BoxSpec {
  Vec3 center;               // m
  Vec3 size{0.1, 0.1, 0.1};  // m
  std::array<int, 3> cells{1, 1, 1};
  double mass = 1.0;    // kg
  double radius = 0.0;  // m; 0: half the smallest cell side
};
GeneratedObject makeBox(const BoxSpec& spec);

/// Plate (cloth): one layer of cells[0]×cells[1] particles in the plane
/// z = center.z, structural and shear LS, TS along lines for bending.
struct PlateSpec {
  Vec3 center;
  double sizeX = 1.0, sizeY = 1.0;  // m
  double thickness = 0.0;           // m; 0: the smallest cell side
  std::array<int, 2> cells{10, 10};
  double mass = 1.0;    // kg
  double radius = 0.0;  // m; 0: half of min(cell side, thickness)
};
GeneratedObject makePlate(const PlateSpec& spec);

/// Ball: the points of a cells³ lattice across the diameter whose centre lies
/// in the ball, LS to neighbours within √3 cells. cells = 1: one particle.
struct BallSpec {
  Vec3 center;
  double radius = 0.1;  // m
  int cells = 1;
  double mass = 1.0;            // kg
  double particleRadius = 0.0;  // m; 0: half a cell
};
GeneratedObject makeBall(const BallSpec& spec);

/// Wheel: two rim rings of rimParticles at ±width/4 along the axis, two hub
/// particles on the axis; rim, cross, diagonal, spoke and axle LS.
struct WheelSpec {
  Vec3 center;
  double radius = 0.1;  // m, outer
  double width = 0.04;  // m
  Vec3 axis{0.0, 1.0, 0.0};
  int rimParticles = 16;
  double mass = 1.0;  // kg
};
GeneratedObject makeWheel(const WheelSpec& spec);

/// A rotation R = (unit axis, angle in rad) applied about `pivot`.
void rotateObject(GeneratedObject& object, const Vec3& pivot, const Vec3& axis, double angle);
/// Roll, pitch, yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll), about `pivot`.
void rotateObjectRpy(GeneratedObject& object, const Vec3& pivot, const Vec3& rollPitchYaw);

/// The default LS stiffness of an object at step δ (N/m): the value for which
/// the fastest mode of the object alone has ω δ = 0.25 by the Gershgorin bound
/// ω² <= Σ_springs κ (1/m_i + 1/m_j), an eighth of the symplectic limit ω δ < 2.
double defaultStiffness(const GeneratedObject& object, double dt);

/// Fills every connector's stiffness and damping from `settings`, using the
/// defaults for unset values: κ from defaultStiffness; μ = 10% of critical
/// damping for two of the object's particles, 0.2 √(κ m / 2); bend stiffness
/// κ_b = bendFactor κ h² (h the spacing; 0 for none); bend damping
/// 0.2 √(κ_b m h² / 2). TS are removed when both bend values are 0.
void resolveSprings(GeneratedObject& object, const SpringSettings& settings, double dt,
                    double bendFactor);

}  // namespace robophi::io
