#pragma once
/// \file
/// Geometry → rigid particle bodies (MODEL §1: an object's particles respect the
/// reference object's mass, centre of mass and volume; here also its inertia).
/// A body's volume is a union of shapes (boxes, cylinders, spheres, triangle
/// meshes) filled with a lattice of particles; their masses are fitted so that
/// the mass, centre of mass and inertia tensor are the ones asked for; LS between
/// lattice neighbours hold it rigid, with the stiffness of objects.h's rule.
/// This is the road from a URDF link or a scene's mesh object to particles.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/build/objects.h"
#include "robophi/vec3.h"

namespace robophi::build {

/// A rigid frame: x = origin + R x_local; R's columns are axes[0..2] (orthonormal, right-handed).
struct Frame {
  /// Origin (m).
  Vec3 origin{};
  /// The columns of R (-): the frame's x, y, z axes in the parent frame.
  std::array<Vec3, 3> axes{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
  /// origin + R local (m).
  Vec3 apply(const Vec3& local) const;
  /// R local.
  Vec3 rotate(const Vec3& local) const;
  /// this ∘ child: the child frame (given in this frame) in this frame's parent.
  Frame then(const Frame& child) const;
  /// The parent frame in this frame.
  Frame inverse() const;
  /// URDF <origin xyz rpy>: R = Rz(yaw) Ry(pitch) Rx(roll) (rad), origin xyz (m).
  static Frame fromXyzRpy(const Vec3& xyz, const Vec3& rpy);
  /// A rotation by `angle` (rad) about `axis` (-, non-zero; normalised), origin 0.
  static Frame fromAxisAngle(const Vec3& axis, double angle);
};

/// Inertia tensor (kg·m²), symmetric: xx, yy, zz, xy, xz, yz (URDF's ixx.. order of meaning).
struct Inertia {
  double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
};

/// Mass, centre of mass and inertia about it (in the frame the positions are given in).
struct MassProperties {
  /// Total mass (kg).
  double mass = 0;
  /// Centre of mass (m).
  Vec3 centerOfMass{};
  /// Inertia about the centre of mass (kg·m²).
  Inertia inertia{};
};
/// The mass properties of point masses mass[i] (kg) at position[i] (m); sizes equal.
MassProperties massProperties(const std::vector<Vec3>& position, const std::vector<double>& mass);
/// Principal moments (kg·m², ascending) of an inertia tensor.
std::array<double, 3> principalMoments(const Inertia& inertia);
/// The inertia tensor of a body turned by the frame's rotation: R I Rᵀ (R's columns =
/// frame.axes), e.g. a URDF <inertial> given in its <origin rpy> frame, in the link frame.
Inertia rotateInertia(const Inertia& inertia, const Frame& frame);

/// A triangle mesh: vertices (m) and triangles of vertex indices.
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int32_t, 3>> triangles;
};
/// The budgets of a mesh file (docs/scene-format.md#limits), checked as it is
/// read and before it is triangulated: the vertex indices (corners) of one face,
/// and Σ corners² of the faces of more than four (assimp's triangulation of a
/// polygon takes time that grows faster than its corners: 0.25 s for one of
/// 1 000 here, minutes for 200 000); then the vertices and faces of all its
/// meshes as its nodes place them (a mesh placed twice counts twice).
inline constexpr std::uint64_t kMaxMeshVertices = 4'000'000;
inline constexpr std::uint64_t kMaxMeshFaces = 4'000'000;
inline constexpr unsigned kMaxMeshFaceIndices = 1'000;
inline constexpr std::uint64_t kMaxMeshPolygonWork = 10'000'000;
/// Reads a mesh (STL binary and ASCII, OBJ, DAE and what else assimp reads), scaled per axis.
/// Throws std::runtime_error naming the file and the problem: missing or not a regular
/// file (readInputFile), unreadable, past a budget, no triangles, a scale factor of 0.
TriangleMesh loadMesh(const std::string& path, const Vec3& scale = {1, 1, 1});

/// One piece of a body's volume, in the body's frame.
struct ShapeSpec {
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  /// The shape's frame in the body frame (URDF <collision><origin>).
  Frame frame{};
  /// Box: full side lengths (m), each > 0.
  Vec3 size{0.1, 0.1, 0.1};
  /// Cylinder, sphere (m), > 0.
  double radius = 0.05;
  /// Cylinder, along its local z (m), > 0.
  double length = 0.1;
  /// kMesh: vertices in the shape frame (m, scale applied).
  TriangleMesh mesh{};
};

/// How a shape sits on a joint's line, the one test of what is a wheel (docs/robots.md
/// "Wheels"): a cylinder whose axis is the line, or a sphere centred on it, each within
/// 1e-3 of its radius (and the cylinder's axis within 1e-3 rad); anything else (a box, a
/// mesh, an eccentric cylinder: a cam) is kNone. `point` on the line and its unit
/// `axis` are in the frame the shape's frame is given in.
enum class RoundAbout { kNone, kCylinder, kSphere };
RoundAbout roundAbout(const ShapeSpec& shape, const Vec3& point, const Vec3& axis);

/// A rigid body of particles whose mass, centre of mass and inertia are the given ones.
struct RigidBodySpec {
  /// The union is the volume filled; empty: a small cluster of particles that
  /// carries the mass properties.
  std::vector<ShapeSpec> shapes{};
  /// Mass (kg), > 0.
  double mass = 1.0;
  /// Centre of mass (m), body frame.
  Vec3 centerOfMass{};
  /// Inertia about the centre of mass, body-frame axes (kg·m²); all zero: the
  /// uniform-density value of the shapes.
  Inertia inertia{};
  /// true: centerOfMass and inertia are ignored; both are the uniform-density
  /// values of the shapes (a scene's mesh object). Needs shapes.
  bool uniformDensity = false;
  /// Points (body frame) that must be particles of the body, in this order (joint particles:
  /// axis centres, axis points, JS arms). Tied rigidly to the body like the others, with mass
  /// taking part in the fit.
  std::vector<Vec3> requiredPoints{};
  /// Lattice spacing (m), >= 0; 0: chosen so that the lattice has about `particleCount` particles.
  double particleSize = 0.0;
  /// The lattice's particle count when particleSize is 0, >= 1.
  int particleCount = 30;
  /// The smallest fitted mass as a fraction of the mean mass, in (0, 1): the
  /// default stiffness rule uses the smallest mass, so a tiny mass makes the body soft.
  double minMassFraction = 0.2;
  /// The farthest a carrier may sit from the centre of mass (m), >= 0; 0: no
  /// limit. Carriers carry inertia the geometry cannot (URDFs with placeholder
  /// inertias ask for radii of gyration of metres); beyond the limit the fit
  /// reaches what it can (RigidBody::fitted false, a note says how far).
  double maxCarrierDistance = 0.0;
  /// Natural frequency of the body's fastest mode (rad/s), > 0: the stiffness rule (objects.h).
  double naturalFrequency = kDefaultNaturalFrequency;
};

/// A body built by makeRigidBody.
struct RigidBody {
  /// Body-frame positions, fitted masses, radii, LS (resolved).
  GeneratedObject object{};
  /// Local index of each required point (RigidBodySpec::requiredPoints order).
  std::vector<int> required{};
  /// Local indices of the carrier particles added outside the geometry (empty: none).
  std::vector<int> carriers{};
  /// Of the particles, body frame.
  MassProperties achieved{};
  /// What was asked for (the uniform-density values filled in), body frame.
  MassProperties target{};
  /// The lattice spacing used (m).
  double spacing = 0.0;
  /// true: achieved matches target (mass 1e-9 relative, centre 1e-6 m, inertia
  /// tensor 1e-6 relative); false: the closest fit found, see notes.
  bool fitted = false;
  /// What the builder had to do, e.g. "inertia beyond the geometry: 6 carriers added".
  std::vector<std::string> notes{};
};
/// Builds the body: the union's lattice at `particleSize` (or the spacing whose
/// lattice has about `particleCount` particles; every shape at least 2 cells
/// across each axis, parts of a mesh thinner than a cell a particle on their
/// surface), mapped affinely to the uniform solid's centre and second moments;
/// the required points; masses fitted (mass 1e-9 relative, centre 1e-6 m,
/// inertia tensor 1e-6 of its trace), each >= minMassFraction × the mean, as
/// near equal as the target allows. When the lattice cannot carry the target,
/// carriers: pairs outside the geometry on the target's principal axes, six near
/// the centre of mass, eight on the diagonals (RigidBody::carriers, notes). LS
/// join lattice neighbours (axis, face and body diagonals); a particle whose
/// neighbours do not span 3-D is tied to its nearest; a body of up to 250
/// particles is checked for mechanisms and braced until rigid. Stiffness and
/// damping by resolveSprings at `naturalFrequency`; no TS.
/// Throws SpecError naming the field for a bad spec.
RigidBody makeRigidBody(const RigidBodySpec& spec);

/// The uniform-density mass properties of the union of `shapes` with total `mass` (kg):
/// exact for one box, cylinder, sphere or closed mesh, sampled otherwise.
MassProperties uniformMassProperties(const std::vector<ShapeSpec>& shapes, double mass);

}  // namespace robophi::build
