#pragma once
/// \file
/// Object generators (MODEL §1: an object is a set of particles that respects
/// the reference object's mass, centre of mass and volume, tied by connectors).
/// Each generator returns the object in local particle indices; ModelBuilder
/// (build/model_builder.h) places it in a model. Connectors start at rest: every
/// rest length and rest angle is the initial one, so the object starts with zero
/// spring energy. Lattice particles have equal masses and sit at the centres of
/// the cells, so that spheres of half a cell tile the object's size exactly.
///
/// Every generator checks its spec first and throws SpecError (naming the field
/// and its value) for a bad one. The connectors come out with stiffness 0:
/// resolveSprings gives them their values.

#include <array>
#include <optional>
#include <vector>

#include "robophi/build/spec_error.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// An object in local indices (0..size()-1).
struct GeneratedObject {
  std::vector<Vec3> position{};  // (n) m
  std::vector<double> mass{};    // (n) kg
  std::vector<double> radius{};  // (n) m
  /// (n) or empty (none): particles the generator fixes, e.g. a robot's base.
  std::vector<bool> fixed{};
  std::vector<LinearSpring> linearSprings{};    // local indices
  std::vector<TorsionSpring> torsionSprings{};  // local indices; stiffness from bend*
  /// The typical distance between neighbours (m): sets default bend stiffness.
  double spacing = 0.0;
  /// Robots (build/robots.h): JS in local indices and their named joints, whose
  /// Joint::connector indexes jointSprings; placed with the name "<object>.<name>".
  std::vector<JointSpring> jointSprings{};
  std::vector<Joint> joints{};
  /// Wheel rims and balls with a round contact surface (local indices; robophi::RimRing).
  std::vector<RimRing> rims{};
  /// Surface mesh (MODEL §3.8, docs/contact.md "Flat faces"): vertices embedded
  /// in the particles (local particle indices), triangles over them (local
  /// vertex indices); empty: the object touches by its particles.
  std::vector<SurfaceVertex> surfaceVertices{};
  std::vector<SurfaceTriangle> surfaceTriangles{};
  /// Half thickness of a sheet surface (m); 0 for a closed surface.
  double surfaceRadius = 0.0;
  /// Treated as rigid by the contact search (ObjectInfo::rigid).
  bool rigid = false;
  /// How contacts treat it (ObjectInfo::contact): a rope's links decide their
  /// friction one by one and do not turn; inertia carriers touch nothing.
  ContactRole contact{};

  std::size_t size() const { return position.size(); }
};

/// The default natural frequency ω (rad/s) of an object's fastest mode, which
/// sets its default LS stiffness (defaultStiffness). 2500 rad/s is ω·δ = 0.25
/// at the default step δ = 1e-4 s: stiff, and 8× inside the symplectic limit
/// ω·δ < 2 there.
inline constexpr double kDefaultNaturalFrequency = 2500.0;

/// The size budget of a model (docs/scene-format.md#limits): the most particles
/// and connectors (LS + TS + JS) one generated object, and one scene, may have.
/// Every generator checks the sizes its spec asks for against it before it
/// allocates anything (SpecError naming the field), so a spec that cannot fit
/// gets a message, not std::bad_alloc or a build that does not end. At the
/// budget a model takes about 300 MB and `robophi validate` (its stability
/// estimate, 200 sweeps over the connectors) a few seconds.
inline constexpr int kMaxParticlesPerObject = 250'000;
inline constexpr std::int64_t kMaxConnectorsPerObject = 1'000'000;

/// The connector parameters of a generated object. Unset values get defaults
/// from the particle masses and the natural frequency (see resolveSprings).
struct SpringSettings {
  /// LS stiffness κ (N/m), >= 0; unset: defaultStiffness(object, naturalFrequency).
  std::optional<double> stiffness{};
  /// LS damping μ (N·s/m), >= 0; unset: 10 % of critical, 0.2 √(κ m_min / 2).
  std::optional<double> damping{};
  /// TS stiffness along lattice lines (N·m/rad), >= 0; 0 means no TS.
  std::optional<double> bendStiffness{};
  /// TS damping (N·m·s/rad), >= 0.
  std::optional<double> bendDamping{};
  /// Natural frequency ω (rad/s), > 0, of the object's fastest mode when
  /// `stiffness` is unset; ignored otherwise.
  double naturalFrequency = kDefaultNaturalFrequency;
};

/// Rope (or chain): `particles` particles from start to end inclusive, LS
/// between neighbours, TS at 180° on consecutive triples when bendStiffness > 0.
struct RopeSpec {
  /// First and last particle centres (m); they must differ.
  Vec3 start{}, end{1.0, 0.0, 0.0};
  /// Number of particles, >= 2.
  int particles = 10;
  /// Total mass (kg), > 0.
  double mass = 1.0;
  /// Particle radius (m), >= 0; 0: half the spacing.
  double radius = 0.0;
};
GeneratedObject makeRope(const RopeSpec& spec);

/// Box (bar, cube): a cells[0]×cells[1]×cells[2] lattice of equal particles
/// filling `size` around `center`, LS to axis, face-diagonal and body-diagonal
/// neighbours, TS along lattice lines.
struct BoxSpec {
  /// Centre (m).
  Vec3 center{};
  /// Side lengths (m), each > 0.
  Vec3 size{0.1, 0.1, 0.1};
  /// Cells (particles) along x, y, z, each >= 1.
  std::array<int, 3> cells{1, 1, 1};
  /// Total mass (kg), > 0.
  double mass = 1.0;
  /// Particle radius (m), >= 0; 0: half the smallest cell side.
  double radius = 0.0;
  /// Give it a surface mesh on its true faces (MODEL §3.8), so that it touches
  /// by flat faces and tips at its true corners. A box with one cell across an
  /// axis gets a sheet at mid-thickness instead; one with a single cell across
  /// two or three axes gets none.
  bool facets = true;
};
GeneratedObject makeBox(const BoxSpec& spec);

/// Plate (cloth): one layer of cells[0]×cells[1] particles in the plane
/// z = center.z, structural and shear LS, TS along lines for bending.
struct PlateSpec {
  /// Centre (m).
  Vec3 center{};
  /// Side lengths along x and y (m), > 0.
  double sizeX = 1.0, sizeY = 1.0;
  /// Thickness (m), >= 0; 0: the smallest cell side.
  double thickness = 0.0;
  /// Cells (particles) along x and y, each >= 1.
  std::array<int, 2> cells{10, 10};
  /// Total mass (kg), > 0.
  double mass = 1.0;
  /// Particle radius (m), >= 0; 0: half of min(cell side, thickness).
  double radius = 0.0;
  /// Give it a surface mesh (MODEL §3.8): a sheet in its plane, touched from
  /// both sides at half its thickness. Needs at least 2 cells along x and y.
  bool facets = true;
};
GeneratedObject makePlate(const PlateSpec& spec);

/// Ball: the points of a cells³ lattice across the diameter whose centre lies
/// in the ball, LS to neighbours within √3 cells. cells = 1: one particle.
struct BallSpec {
  /// Centre (m).
  Vec3 center{};
  /// Radius (m), > 0.
  double radius = 0.1;
  /// Lattice points across the diameter, in [1, 400].
  int cells = 1;
  /// Total mass (kg), > 0.
  double mass = 1.0;
  /// Particle radius (m), >= 0; 0: half a cell (the ball's radius for cells = 1).
  double particleRadius = 0.0;
  /// A lattice of more than one particle meets the environment as a rigid sphere of
  /// `radius` about its mass centre (robophi::RimRing, docs/contact.md "Round balls").
  bool round = true;
};
GeneratedObject makeBall(const BallSpec& spec);

/// Wheel: two rim rings of rimParticles at ±width/4 along the axis, two hub
/// particles on the axis; rim, cross, diagonal, spoke and axle LS.
struct WheelSpec {
  /// Centre (m).
  Vec3 center{};
  /// Outer radius (m), > 0.
  double radius = 0.1;
  /// Width along the axis (m), > 0.
  double width = 0.04;
  /// Axle direction (-), non-zero; normalised.
  Vec3 axis{0.0, 1.0, 0.0};
  /// Particles per rim ring, >= 3.
  int rimParticles = 16;
  /// Total mass (kg), > 0.
  double mass = 1.0;
  /// Distance between the two hub particles along the axis (m), >= 0; 0: width/2
  /// (between the rings). The span the wheel's bearings hold it by: its camber and
  /// toe stiffness on its hubs grow with its square.
  double hubSpan = 0.0;
};
GeneratedObject makeWheel(const WheelSpec& spec);

/// Appends a particle to `object` (not fixed); returns its local index.
int addParticle(GeneratedObject& object, const Vec3& position, double mass, double radius);
/// Appends an LS between local particles a and b at rest at their distance, its
/// stiffness and damping (0) to be resolved; returns its index.
int addLink(GeneratedObject& object, int a, int b);

/// A rotation R = (axis, angle in rad) applied about `pivot`; the axis (-) must
/// be non-zero and finite, the angle finite.
void rotateObject(GeneratedObject& object, const Vec3& pivot, const Vec3& axis, double angle);
/// Roll, pitch, yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll), about `pivot`.
void rotateObjectRpy(GeneratedObject& object, const Vec3& pivot, const Vec3& rollPitchYaw);

/// The default LS stiffness of an object (N/m): the value for which the fastest
/// mode of the object alone has the natural frequency ω (rad/s, > 0) by the
/// Gershgorin bound ω² <= Σ_springs κ (1/m_i + 1/m_j), i.e. κ = ω² / max_i Σ.
/// 0 for an object without LS.
double defaultStiffness(const GeneratedObject& object, double naturalFrequency);

/// Fills every connector's stiffness and damping from `settings`, using the
/// defaults for unset values: κ from defaultStiffness; μ = 10% of critical
/// damping for two of the object's particles, 0.2 √(κ m / 2); bend stiffness
/// κ_b = bendFactor κ h² (h the spacing; 0 for none); bend damping
/// 0.2 √(κ_b m h² / 2). TS are removed when both bend values are 0.
void resolveSprings(GeneratedObject& object, const SpringSettings& settings,
                    double bendFactor = 0.0);

}  // namespace robophi::build
