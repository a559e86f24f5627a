#pragma once
// Edges (MODEL §3.8 "Edges", docs/contact.md "Edges"): two faceted bodies
// touching along crossed edges, where no vertex of either is inside the other
// (two cubes' ridges crossed at right angles), push apart at the edges' closest
// points. An edge contact is a facet contact whose touching side is a point of
// an edge (Contact::edgeVertex, edgeWeight) and whose touched side is a point
// of an edge of the other body's triangle `facet`: the same law, kinematics,
// force spreading and stability sums as a vertex on a triangle (facets.h).

#include "collision/contact_tables.h"

namespace robophi {

/// Whether each edge is a ridge (ContactScratch::edgeRidge), from
/// scratch.vertexPosition and scratch.triangleNormal (updateSurfacePositions).
void updateEdgeShapes(ContactScratch& scratch);
/// Two faceted leaves of different objects: their edge pairs that touch, into
/// scratch.edgeCandidates (the lower object's edge first).
void leafEdgesOnLeafEdges(const Model& model, ContactScratch& scratch, const TreeNode& a,
                          const TreeNode& b);
/// Reduces the candidates to one contact per (edge, object), the shallowest
/// (the lowest edge index on a tie), appended to scratch.treeContacts. (As
/// for separating axes, two convex bodies overlap by the least of their
/// candidates' depths: taking the deepest, a box's edge lying 0.33 mm into
/// another along the vertical flipped at every evaluation to a pair 3.05 mm
/// deep along a sideways axis, and the adaptive step stalled.) A contact
/// starts only at the surface: one deeper than kEdgeOnset of its shorter edge
/// is kept only when it goes on (`previous`, the friction history, has an
/// edge contact with the same body from this edge or the next one along its
/// ridge). An edge pair's test switches on inside a body (its normal entering
/// the cones, its crossing leaving a vertex), and a contact born there
/// releases κ_c d²/2 from nothing.
void resolveEdgeCandidates(const Model& model, const std::vector<Vec3>& velocity,
                           const std::vector<Contact>& previous, ContactScratch& scratch);
/// The deepest an edge contact starts, as a fraction of its shorter edge (-).
/// The bin of 180 boxes started overlapping (stress/box_bin_overlapping.json)
/// takes 4 945 steps (41 rejected) without edges; with edges, at 0.05 its
/// step stalled at 0.3 ms, at 0.005 it takes 5 101 (174), at 0.001 4 929 (72).
/// Pairs of ridges still apart bound the step (ContactScratch::edgeApproachStep,
/// in Evaluation::contactCriticalStep): closing at their speed, they may not
/// pass half the onset (a cube falling onto a crossed ridge took steps of
/// 0.026 s, closed 5 mm in one, and sank to its vertices, 16.8 mm).
inline constexpr double kEdgeOnset = 0.005;

/// The geometry of two edges, x0→x1 with outward face normals a1, a2 and y0→y1
/// with b1, b2: whether they touch as edges, and where. They do when the
/// direction n ∝ (x1 − x0) × (y1 − y0) from the second to the first lies in
/// the second's normal cone and -n in the first's, by at least kEdgeConeMargin
/// (the edge pair is a face of the bodies' Minkowski difference: a supporting
/// pair, not a vertex on a face or two faces flat on each other), the closest
/// points of the two lines lie inside both edges, and the gap along n between
/// them, less `radius` (the sheets' half thicknesses), is negative and under
/// half the shorter edge deep.
struct EdgeHit {
  double s = 0.0, t = 0.0;  ///< along the first and the second edge (-)
  double depth = 0.0;       ///< (m), < 0
  double shorter = 0.0;     ///< the shorter edge's length (m)
  Vec3 normal;              ///< from the second body to the first
};
inline constexpr double kEdgeConeMargin = 0.02;  ///< sin of ~1.1° (-)
/// The pair's test without its depth: whether the two edges face each other
/// as a pair (the cones and the closest points), its gap in out.depth.
bool edgePair(const Vec3& x0, const Vec3& x1, const Vec3& a1, const Vec3& a2, const Vec3& y0,
              const Vec3& y1, const Vec3& b1, const Vec3& b2, double radius, EdgeHit& out);
bool edgesTouch(const Vec3& x0, const Vec3& x1, const Vec3& a1, const Vec3& a2, const Vec3& y0,
                const Vec3& y1, const Vec3& b1, const Vec3& b2, double radius, EdgeHit& out);

}  // namespace robophi
