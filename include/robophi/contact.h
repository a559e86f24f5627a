#pragma once
/// \file
/// Contact (MODEL §3, docs/contact.md): the environment the particles collide
/// with, the contact settings of a model, and the contact records a State carries
/// from step to step (their friction anchors).
///
/// The contact stage (src/collision/) finds every touching pair of particles with
/// one sphere tree per object and a broad phase over objects (§3.2), applies the
/// visco-elastic normal force (§3.1) and Coulomb friction (§3.3) realised with a
/// tangential anchor spring, and the medium's viscosity (§3.4).

#include <compare>
#include <cstdint>
#include <string>
#include <vector>

#include "robophi/vec3.h"

namespace robophi {

struct Model;
struct State;

/// A half-space the particles stay above: the ground, or a wall.
struct GroundPlane {
  /// A point of the plane (m).
  Vec3 point{0.0, 0.0, 0.0};
  /// Unit normal pointing out of the solid (-).
  Vec3 normal{0.0, 0.0, 1.0};
  /// Index into Model::materials.
  std::int32_t material = 0;
};

/// A terrain z = h(x, y): heights on a regular grid over an x-y rectangle,
/// bilinear between samples. Outside the rectangle there is no terrain.
struct Heightfield {
  /// x, y of sample (0, 0) (m).
  double originX = 0.0, originY = 0.0;
  /// Distance between samples along x and y (m), > 0.
  double cellSizeX = 1.0, cellSizeY = 1.0;
  /// Samples along x (columns) and y (rows), >= 2 each.
  std::int32_t columns = 0, rows = 0;
  /// Heights (m), (rows × columns): heights[j * columns + i] at (x0 + i dx, y0 + j dy).
  std::vector<double> heights;
  /// Index into Model::materials.
  std::int32_t material = 0;

  /// Whether (x, y) lies over the grid.
  bool covers(double x, double y) const;
  /// h(x, y) (m) and its gradient (dh/dx, dh/dy) by bilinear interpolation;
  /// (x, y) is clamped onto the grid.
  double heightAt(double x, double y, double* dhdx = nullptr, double* dhdy = nullptr) const;
  /// The terrain's unit normal at (x, y), continuous across cell edges: the
  /// samples' gradients (central differences, one-sided at the border)
  /// interpolated bilinearly, then normalised. (The bilinear surface's own
  /// gradient jumps across cell edges; a contact depth measured along it would
  /// make the contact energy jump there.)
  Vec3 normalAt(double x, double y) const;
  /// The smoothed gradient g = (gx, gy) normalAt is made of at (x, y), and its
  /// derivatives along x (dgdx = (∂gx/∂x, ∂gy/∂x)) and y, per cell.
  void smoothedGradientAt(double x, double y, double g[2], double dgdx[2], double dgdy[2]) const;
};

/// A fixed oriented box.
struct BoxObstacle {
  /// Centre (m).
  Vec3 center;
  /// Half sizes along the box's own axes (m), > 0.
  Vec3 halfExtents{0.5, 0.5, 0.5};
  /// The box's axes in the world frame: orthonormal, right-handed (-).
  Vec3 axisX{1.0, 0.0, 0.0}, axisY{0.0, 1.0, 0.0}, axisZ{0.0, 0.0, 1.0};
  std::int32_t material = 0;
};

/// A fixed sphere.
struct SphereObstacle {
  Vec3 center;
  /// Radius (m), > 0.
  double radius = 0.5;
  std::int32_t material = 0;
};

/// Everything fixed that particles collide with, and the medium around them.
/// Environment items are numbered planes first, then heightfields, boxes, spheres.
struct Environment {
  std::vector<GroundPlane> planes;
  std::vector<Heightfield> heightfields;
  std::vector<BoxObstacle> boxes;
  std::vector<SphereObstacle> spheres;
  /// Viscosity of the medium k (N·s/m per particle, MODEL §3.4): a particle moving
  /// at V feels -k (V·n) V̂ where its surface faces the motion. 0: no medium.
  double viscosity = 0.0;

  std::int32_t itemCount() const {
    return static_cast<std::int32_t>(planes.size() + heightfields.size() + boxes.size() +
                                     spheres.size());
  }
};

/// Contact parameters for one pair of objects (or an object and the environment),
/// replacing the combination of their materials.
struct ContactPairOverride {
  /// Object indices; objectB = -1 means every environment item.
  std::int32_t objectA = 0, objectB = -1;
  /// κ_c (N/m), μ_c (N·s/m), μ_s, μ_k (-).
  double stiffness = 1.0e4, damping = 10.0, staticFriction = 0.5, kineticFriction = 0.4;
};

/// How contacts are found and computed (docs/contact.md).
struct ContactSettings {
  /// Contact stage on or off.
  bool enabled = true;
  /// Particles of one object collide with each other unless a connector ties them.
  bool selfCollision = true;
  /// Tangential anchor stiffness k_t = ratio × κ_c (-); §3.3 sticking.
  double tangentialStiffnessRatio = 0.5;
  /// Tangential anchor damping as a fraction of critical (-): c_t = ratio × 2 √(k_t m_eff),
  /// m_eff = m_a m_b / (m_a + m_b) (the particle's mass against the environment or a
  /// fixed particle). 1: a suddenly loaded sticking contact does not overshoot.
  double tangentialDampingRatio = 1.0;
  /// MODEL §3.3 "V ≠ 0" tolerance (m/s): a sliding contact group sticks again
  /// below it; between 0 and it, friction falls from μ_s to μ_k (breaking away).
  double stickVelocity = 1.0e-4;
  /// MODEL §3.3 sliding friction's speed scale v_S (m/s): a contact sliding at
  /// |V| has μ(V) = μ_k + (μ_s - μ_k) exp(-(|V|/v_S)²), μ_s at the start of a
  /// slip and μ_k once it is fast (Stribeck); 0: μ_k at any speed (the paper's
  /// law).
  double stribeckVelocity = 0.0;
  /// MODEL §3.3 rolling: friction acts at the contact point, single particles
  /// spin (State::spin) and objects turn as a whole. false: friction acts at the
  /// particle centres and nothing spins (the paper's model).
  bool rolling = true;
  /// Most particles in a leaf of an object's sphere tree (>= 1).
  std::int32_t leafSize = 4;
  /// Objects flagged ObjectInfo::rigid move their sphere tree as a whole by the
  /// rigid motion of three reference particles instead of refitting it; the
  /// node spheres grow by this margin, as a fraction of the object's smallest
  /// particle radius (-), to cover the particles' deviation from that motion.
  double rigidTreeMargin = 0.5;
  /// Skin of the grid particles' neighbour list (docs/contact.md "Neighbour
  /// list"), as a fraction of the grid cell h (the largest grid particle's
  /// diameter) (-): the list keeps every pair closer than r_a + r_b + skin and is
  /// rebuilt only when some grid particle has moved more than skin / 2 since its
  /// build. The contacts found are those of a grid search at every evaluation,
  /// in the same order. The tree objects' pair list uses the same fraction of
  /// their largest particle's diameter. 0: no lists (the grid is rebuilt and
  /// the trees searched at every evaluation).
  double neighbourSkin = 0.1;
  /// Overrides by object pair; looked up by binary search when not empty.
  std::vector<ContactPairOverride> pairOverrides;
};

/// A contact between particle `a` and either particle `other` (> a) or the
/// environment item -1 - other. An Evaluation lists the contacts at its state,
/// sorted by key(); the step commits them as the State's friction history.
struct Contact {
  // (The fields a step reads back from the friction history come first, in
  // its first 128 bytes: the key, the regime, the anchor and what moves or
  // loads it; the geometry and the outputs after them.)
  std::int32_t a = -1;
  std::int32_t other = -1;
  /// Facet contacts (MODEL §3.8, docs/contact.md "Flat faces"): the surface
  /// vertex (index into Model::surfaceVertices) that touches, or -1 when the
  /// touching side is particle a itself. A vertex contact's `a` is the vertex's
  /// heaviest-weighted particle (a label for the key and the outputs).
  std::int32_t vertex = -1;
  /// Friction regime (MODEL §3.3), decided with the other contacts between the
  /// same two bodies: 0 sticking, 1 sliding, 2 breaking away (the load above
  /// μ_s F_n, friction held at μ_s F_n).
  std::int32_t sliding = 0;
  /// Friction anchor (m): p_a - p_other (pair) or p_a (environment) where the
  /// contact stuck; δ_t is the tangential part of the displacement from it.
  Vec3 anchor;
  /// Elastic energy of the friction anchor ½ k_t |δ_t|² (J) at the last evaluation.
  double anchorEnergy = 0.0;
  /// Velocity (m/s) of the contact point relative to the other body that the
  /// rotation of the two bodies adds (particle spin, or an object's rotation:
  /// MODEL §3.3 rolling), tangential. The step moves the anchor by -rollVelocity·δ,
  /// so δ_t measures the slip of the contact points, not of the particle centres.
  Vec3 rollVelocity;
  /// How far (m) the anchor has given way since the contact started breaking
  /// away: past the anchor's elastic range μ_s F_n / k_t (summed over the
  /// contacts of its body pair) the pair slides. 0 when sticking or sliding.
  double giveWay = 0.0;
  /// Tangential relative velocity (m/s) at the last evaluation: a sliding
  /// contact whose slip reverses from one evaluation to the next sticks again.
  Vec3 slip;
  /// Friction force F_t on a (N), tangential, at the last evaluation (an
  /// output: the state hash leaves it out, it follows from the other fields).
  Vec3 frictionForce;
  /// d (m): distance minus radii, < 0 when it touches (MODEL §3.1).
  double depth = 0.0;
  /// Normal force F_n (N), >= 0, at the last evaluation.
  double normalForce = 0.0;
  /// k̂: unit normal from the other body to a (-).
  Vec3 normal;
  /// The triangle (index into Model::surfaceTriangles) the contact point lies
  /// on, or -1 when the other side is a particle or the environment. A facet
  /// contact's `other` is the first particle of the triangle's object.
  std::int32_t facet = -1;
  /// A wheel rim's or a ball's contact (Model::rims): its index, or -1. The ring
  /// (ball) carries it as a rigid circle (sphere; docs/contact.md "Round rims");
  /// `a` is its first particle, and the contact point is `arm` from its mass centre.
  std::int32_t rim = -1;
  Vec3 arm;
  /// Barycentric weights (-) of the contact point on `facet` (sum 1).
  Vec3 facetWeights;
  /// Edge contacts (MODEL §3.8, docs/contact.md "Edges"): the touching side is
  /// the point (1 - s) x_vertex + s x_edgeVertex of the surface edge from
  /// `vertex` to `edgeVertex`, s = edgeWeight, and the touched side a point of
  /// an edge of `facet` (one of facetWeights is 0). -1 for every other contact.
  std::int32_t edgeVertex = -1;
  double edgeWeight = 0.0;

  bool withEnvironment() const { return other < 0; }
  std::int32_t environmentItem() const { return -1 - other; }
  /// A contact of a surface vertex or against a triangle (MODEL §3.8).
  bool involvesFacets() const { return vertex >= 0 || facet >= 0; }
  /// Sort key: (a, other, vertex, edgeVertex) with environment contacts after
  /// a's particle contacts, a's own contacts before its vertices' contacts with
  /// the same partner, and a vertex's contact before its edges'.
  struct Key {
    std::uint64_t pair = 0;
    std::uint32_t vertex = 0;
    std::uint32_t edge = 0;
    auto operator<=>(const Key&) const = default;
  };
  Key key() const {
    return {(static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
                static_cast<std::uint32_t>(other),
            static_cast<std::uint32_t>(vertex + 1), static_cast<std::uint32_t>(edgeVertex + 1)};
  }
};

/// Counters of the last contact evaluation.
struct ContactStats {
  /// Particle-particle distance tests of the narrow phase.
  std::int64_t pairTests = 0;
  /// Sphere-sphere tests between tree nodes.
  std::int64_t nodeTests = 0;
  /// Particle-environment tests.
  std::int64_t environmentTests = 0;
  std::int64_t particleContacts = 0;
  std::int64_t environmentContacts = 0;
  /// Contacts of surface vertices or against triangles (MODEL §3.8), and the
  /// point-triangle distance tests that found them.
  std::int64_t facetContacts = 0;
  std::int64_t facetTests = 0;
  /// Deepest penetration -d (m) and as a fraction of the smaller radius (-).
  double maxPenetration = 0.0;
  double maxPenetrationFraction = 0.0;
  /// 1 when this evaluation rebuilt the grid particles' neighbour list, else 0.
  std::int64_t neighbourListBuilds = 0;
  /// 1 when this evaluation rebuilt the tree objects' pair list, else 0.
  std::int64_t treePairListBuilds = 0;
};

/// The deepest penetration of `contacts` as a fraction of the smaller radius
/// involved (0 when nothing touches).
double deepestPenetrationFraction(const Model& model, const std::vector<Contact>& contacts);

}  // namespace robophi
