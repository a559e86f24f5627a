#pragma once
// Flat faces (MODEL §3.8, docs/contact.md "Flat faces"): objects with a surface
// mesh (boxes, plates) touch by it. Their vertices are embedded in the particles
// (x_v = Σ w_k p_k, Σ w_k = 1); a particle of another body, or a vertex of
// another faceted body, touches the closest of the mesh's triangles; a faceted
// body's vertices, not its particles, touch the environment. The force goes to
// the triangle's vertices by barycentric weights and on to the particles by the
// vertices' weights, so net force, torque and power are those of the contact.
// The normal force and friction are the particle contacts' law
// (contact_force.cpp), given the touching point's kinematics by facetKinematics.

#include <cstdint>
#include <vector>

#include "collision/contact_tables.h"
#include "robophi/surface_points.h"

namespace robophi {

/// The margin (m) by which a faceted tree's node spheres grow so that they enclose
/// the surface: the farthest vertex of a triangle (or a vertex) from the particle
/// that carries it, beyond that particle's radius, plus the sheet radius, with
/// 25% slack for deformation. `members` are the tree's particles.
double facetTreeMargin(const Model& model, const std::vector<Vec3>& position,
                       const ContactTables& tables, const std::vector<std::int32_t>& members);

// (surfaceVertexPoint and touchingPoint: robophi/surface_points.h.)

/// Vertex positions x_v = Σ w_k p_k of every surface vertex into
/// scratch.vertexPosition, and each faceted triangle's unit normal into
/// scratch.triangleNormal (zero for a degenerate one).
void updateSurfacePositions(const Model& model, const std::vector<Vec3>& position,
                            ContactScratch& scratch);

/// Two touching leaves of different objects, at least one faceted: candidates
/// (particle or vertex of one, triangle of the other) for resolveFacetCandidates.
void leavesWithFacets(const Model& model, const std::vector<Vec3>& position,
                      ContactScratch& scratch, const TreeNode& a, const TreeNode& b);
/// A particle of another body against the triangles a faceted leaf carries.
void particleOnLeafFacets(ContactScratch& scratch, const TreeNode& leaf, std::int32_t particle);
/// The vertices a faceted leaf carries against environment item `item`:
/// contacts appended to scratch.treeContacts.
void leafVerticesOnEnvironment(const Model& model, ContactScratch& scratch, const TreeNode& leaf,
                               std::int32_t item);
/// Reduces the candidates to one contact per (particle or vertex, faceted
/// object): the closest triangle (lowest index on a tie), appended to
/// scratch.treeContacts when it touches, with depth, normal, facet and weights.
void resolveFacetCandidates(const Model& model, const std::vector<Vec3>& position,
                            ContactScratch& scratch);

/// What the contact law needs of a facet contact: the relative position of the
/// touching point and the point it touches (the triangle's point at the contact's
/// barycentric weights, or the origin for the environment), their relative
/// velocity, the pair's effective mass, and the history contact with its anchor
/// moved to the current contact point (a body-fixed point: the anchor's
/// tangential offset is kept while the contact point moves across the faces).
struct FacetKinematics {
  Vec3 relative;
  Vec3 relativeVelocity;
  double reducedMass = 0.0;
  Contact previous;
  bool hasPrevious = false;
  /// A length for the penetration fraction (m): the touching particle's radius.
  double radius = 0.0;
};
/// The vertex of a vertex contact (c.vertex >= 0) as a rigid tree body carries
/// it (docs/model.md §7 "Contacts on rigid trees"): `tree` is -1 unless one
/// tree body carries the vertex whole (ContactTables::vertexOnBody); `point`
/// is the vertex (its sheet's thickness inward along the contact's normal) and
/// `inverseMass` the contact law's inverse effective mass there (1/kg).
struct FacetCarrier {
  std::int32_t tree = -1, body = -1;
  Vec3 point;
  double inverseMass = 0.0;
};
FacetCarrier vertexCarrier(const Model& model, const ContactTables& tables,
                           const std::vector<Vec3>& position, const Contact& c);

void facetKinematics(const Model& model, const ContactTables& tables,
                     const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                     const Contact* before, const Contact& c, FacetKinematics& out);
/// Adds the force `onA` (N) on the touching side and -onA on the touched side,
/// spread over their particles by the vertices' and barycentric weights.
void distributeFacetForce(const Model& model, const Contact& c, const Vec3& onA,
                          std::vector<Vec3>& force);
/// A contact with a triangle (Contact::facet): its stiffness and damping (N/m,
/// N·s/m) into the stability sums of the triangle's particles, which carry the
/// touched point (x_q = Σ_j β_j Σ_k w_jk p_k). Particle k of vertex j takes
/// ½ R |β_j w_jk| of them, R = Σ|w| of the touching side + Σ_jk |β_j w_jk|: its
/// Gershgorin row of the contact's κ g gᵀ, |g_k| Σ|g|, over the pair rule's
/// factor 2 (2 Σκ / m). (Not the object's first particle, the contact's label:
/// given every contact on a light cloth, it held a cloth draped over a box to
/// steps of 8.5e-7 s.)
void addTriangleRates(const Model& model, const Contact& c, const law::Rates& rates,
                      std::vector<law::Rates>& sums);
/// A vertex moves its heaviest particle by more than the particle alone: the
/// extra stiffness (N/m) that particle's stability sum gets, Σ|w| |w_a| - 1 times
/// `stiffness` (0 when none).
double facetExtraStiffness(const Model& model, double stiffness, const Contact& c);

}  // namespace robophi
