#pragma once
// The contact stage's data (MODEL §3): the tables derived once from the model
// (ContactTables: exclusion lists, material-pair table, which particles go to
// the grid and which objects get a sphere tree), owned by the CompiledModel and
// rebuilt by the edits that change them; and the per-evaluation scratch
// (ContactScratch: sphere-tree topology and spheres, grid, the next contact
// list), owned by a Workspace. Nothing here allocates in a step once the
// buffers have grown to the scene's size.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "collision/contact_law.h"
#include "collision/environment.h"
#include "robophi/contact.h"
#include "robophi/model.h"

namespace robophi {

/// Contact parameters of a pair after combining materials (docs/contact.md).
struct PairParameters {
  double stiffness = 0.0;            // κ_c (N/m)
  double damping = 0.0;              // μ_c (N·s/m)
  double staticFriction = 0.0;       // μ_s (-)
  double kineticFriction = 0.0;      // μ_k (-)
  double tangentialStiffness = 0.0;  // k_t (N/m)
  /// c_t = tangentialDampingRatio × 2 √(k_t m_eff), m_eff the pair's effective
  /// mass at the contact point (its rotation included).
  double tangentialDampingRatio = 0.0;  // (-)
  /// μ_r (-): rolling resistance torque μ_r r F_n against the rolling (0: none).
  double rollingResistance = 0.0;
  /// v_S (m/s): sliding friction's speed scale (law::slidingCoefficient).
  double stribeckVelocity = 0.0;
};

/// A node of an object's sphere tree. Its particles are
/// ContactScratch::treeParticles[first, first + count); children are contiguous.
struct TreeNode {
  Vec3 center;
  double radius = 0.0;
  std::int32_t first = 0, count = 0;
  std::int32_t firstChild = -1, childCount = 0;
  /// The object whose tree holds the node.
  std::int32_t object = -1;
  /// Rigid trees (ObjectInfo::rigid): the centre in the tree's reference frame
  /// at build (m), moved each evaluation by the frame's rigid motion.
  Vec3 restCenter;
  bool isLeaf() const { return childCount == 0; }
};

/// An object with a sphere tree (two or more particles, or one large particle).
struct TreeObject {
  std::int32_t object = -1;
  /// Set when the tree is built (ContactScratch::trees): its root node and the
  /// range [nodeBegin, nodeEnd) of its nodes in ContactScratch::nodes.
  std::int32_t rootNode = 0;
  std::int32_t nodeBegin = 0, nodeEnd = 0;
  bool allFixed = false;
  /// The object has a surface mesh (MODEL §3.8): its node spheres, grown by
  /// `margin` (m) (outerRadius), enclose its vertices and triangles as well as
  /// its particles.
  bool faceted = false;
  double margin = 0.0;
  /// Rigid (ObjectInfo::rigid): three reference particles whose frame moves the
  /// tree (no refit), and that frame at build (origin p_ref[0], axes).
  bool rigid = false;
  std::int32_t reference[3] = {-1, -1, -1};
  Vec3 restAxes[3]{};
};

/// What the contact stage derives from the model alone.
struct ContactTables {
  /// Exclusion lists (CSR): partners j > i sharing an LS/TS/JS with i, sorted,
  /// in exclusionPartner[exclusionStart[i], exclusionStart[i + 1]).
  std::vector<std::int32_t> exclusionStart;    // (particleCount + 1)
  std::vector<std::int32_t> exclusionPartner;  // (exclusions)
  /// Material of each particle (its object's), (particleCount).
  std::vector<std::int32_t> particleMaterial;
  /// Object of each particle, or -1, (particleCount).
  std::vector<std::int32_t> particleObject;
  /// 1 for the particles of an object whose ContactRole::frictionPerParticle
  /// is set (a rope's), 0 for the others, (particleCount). Their contacts decide
  /// friction one by one, not with their body's (a rope drapes over edges with
  /// opposite loads on its two sides).
  std::vector<std::uint8_t> frictionAlone;
  /// 1 for the particles of an object whose ContactRole::turns is false (a
  /// rope's), (particleCount): their contact points do not turn (MODEL §3.3: a
  /// rope's neighbourhood rotation is its bending, not a rolling body's; it
  /// stiffened the contacts' tangential coupling so much that a rope on a box
  /// edge needed 4e-8 s steps).
  std::vector<std::uint8_t> noTurning;
  /// Every contact body (contact_force.cpp's group key) is one particle: each
  /// object has one particle or is a rope. Then every friction group (MODEL
  /// §3.3, a pair of bodies) holds one contact and decides on its own.
  bool singleParticleBodies = true;
  /// 1 / J_i (1/(kg·m²)) of the particles that spin on their own (those no LS
  /// ties to another: J = 2/5 m r², a solid sphere), 0 for the others,
  /// (particleCount). The others turn with their LS neighbours (CSR, both
  /// directions): rollNeighbour[rollNeighbourStart[i], rollNeighbourStart[i + 1]).
  std::vector<double> inverseSpinInertia;
  /// (particleCount) the rigid tree (Model::rigidTrees) and body a particle
  /// carries the surface of, or -1 (docs/model.md §7).
  std::vector<std::int32_t> treeOf, treeBodyOf;
  /// (particleCount) 1 for a particle that moves under the contacts' loads: a free
  /// particle, or one a rigid tree's body carries; 0 for a fixed particle. Two
  /// particles that do not move never touch, and one that does not move never
  /// meets the environment.
  std::vector<std::uint8_t> movable;
  /// (particleCount) the inverse mass the contact law sees at a particle (1/kg): its
  /// own, or for a rigid tree's particle a bound on its body's inverse effective
  /// mass at its points, 1/m + r²/I_min (docs/model.md §7); 0: fixed.
  std::vector<double> contactInverseMass;
  std::vector<std::int32_t> rollNeighbourStart;  // (particleCount + 1)
  /// The rim ring (Model::rims) each particle belongs to, or -1, (particleCount):
  /// rim particles meet the environment through their ring's round surface.
  std::vector<std::int32_t> rimOf;
  std::vector<std::int32_t> rollNeighbour;
  /// Material-pair table, (materials × materials); environment uses the item's material.
  std::vector<PairParameters> materialPairs;
  std::int32_t materialCount = 0;
  /// Environment item materials, (environment items).
  std::vector<std::int32_t> environmentMaterials;
  /// Each item's highest point and steepness, for culling (environmentReach).
  std::vector<EnvironmentReach> environmentReaches;
  /// Bounding boxes of the environment items (m); planes get an infinite box.
  std::vector<Vec3> environmentLow, environmentHigh;
  /// Single small particles handled by the grid, ascending particle index.
  std::vector<std::int32_t> gridParticles;
  /// Grid cell size h (m) = the largest grid particle's diameter.
  double cellSize = 0.0;
  /// Objects with a sphere tree (their nodes are built in the scratch).
  std::vector<TreeObject> trees;
  /// Particles of each tree object, ascending, (trees).
  std::vector<std::vector<std::int32_t>> treeMembers;
  /// Facets (MODEL §3.8). Per object: 1 if it touches by its surface mesh.
  std::vector<std::int8_t> objectFaceted;  // (objects)
  /// Per object: 1 if all its particles are fixed.
  std::vector<std::int8_t> objectFixed;  // (objects)
  /// The particle that carries each vertex (its largest weight), (vertices).
  std::vector<std::int32_t> vertexOwner;
  /// Each vertex's inverse effective mass as the contact law sees it (1/kg),
  /// (vertices): Σ w_k² × contactInverseMass_k over its particles, or, for a
  /// vertex carried whole by one rigid tree body, that body's at the vertex
  /// (classifyCarriers' bound, 1/m + λ_max([r]×ᵀ I⁻¹ [r]×)).
  std::vector<double> vertexInverseMass;
  /// 1 where a vertex is carried whole by one rigid tree body (the owner's:
  /// treeOf, treeBodyOf of vertexOwner), (vertices).
  std::vector<std::int8_t> vertexOnBody;
  /// Per particle, the vertices and the triangles it carries (CSR): a sphere-tree
  /// leaf holding the particle stands for them. A triangle's carrier is the
  /// particle of largest total weight over its three vertices.
  std::vector<std::int32_t> ownedVertexStart, ownedVertex;      // (particles + 1), (vertices)
  std::vector<std::int32_t> ownedTriangleStart, ownedTriangle;  // (particles + 1), (triangles)
  /// Per surface vertex, the triangles it is a corner of (CSR): the faces a
  /// vertex probe presses with (facets.cpp, "Which face").
  std::vector<std::int32_t> vertexTriangleStart, vertexTriangle;  // (vertices + 1), (3 triangles)
  /// The edges of faceted objects' surface meshes that two triangles of the
  /// object share (MODEL §3.8 "Edges"): vertex[0] < vertex[1], the two
  /// triangles, and the vertex of each triangle off the edge. An edge's
  /// carrier is its first triangle's; edges are listed by carrier as triangles.
  struct SurfaceEdge {
    std::array<std::int32_t, 2> vertex{-1, -1}, triangle{-1, -1}, opposite{-1, -1};
  };
  std::vector<SurfaceEdge> edges;
  std::vector<std::int32_t> ownedEdgeStart, ownedEdge;  // (particles + 1), (edges)
  /// Model::noContactPairs: object pairs {a < b} that never touch (sorted).
  std::vector<std::array<std::int32_t, 2>> noContactPairs;
  /// ObjectInfo::contactGroup per object (-1: none), or empty when no object has one.
  std::vector<std::int32_t> objectContactGroup;
  /// ContactSettings::pairOverrides with objectA <= objectB (or objectB = -1), sorted.
  std::vector<ContactPairOverride> overrides;
};

/// Builds the tables of `model`.
ContactTables compileContactTables(const Model& model);

/// The rigid motion of a round rim's ring or a round ball (contact_force.cpp,
/// MODEL §3.1): mass centre c (m), its velocity (m/s), ω (rad/s), Σ r̂_k, the
/// mass M (kg), radius R (m) and Ṙ (m/s), and A⁻¹ (packed) with its largest
/// eigenvalue (1/(kg·m²)).
struct RingMotion {
  Vec3 center, velocity, omega;
  Vec3 radialSum;
  double mass = 0.0, radius = 0.0, radiusRate = 0.0;
  double inverse[6]{};
  double largestInverse = 0.0;
};

/// The grid particles' Verlet neighbour list (docs/contact.md "Neighbour
/// list"): for each grid particle (in ContactTables::gridParticles order) its
/// partners j > i closer than r_i + r_j + skin at the build, ascending. Valid
/// while no grid particle has moved more than skin / 2 from its position at the
/// build (nor changed its radius): then every touching pair is in it.
struct NeighbourList {
  /// The ContactScratch::revision it was built for; -1: none.
  std::int64_t revision = -1;
  double skin = 0.0;  // (m)
  /// Positions and radii of the grid particles at the build, (gridParticles).
  std::vector<double> referenceX, referenceY, referenceZ, referenceRadius;
  /// CSR: partner[start[k], start[k + 1]) of grid particle k, (gridParticles + 1).
  std::vector<std::int32_t> start;
  std::vector<std::int32_t> partner;
  /// Builds so far (the first one included).
  std::int64_t builds = 0;
};

/// The tree objects' pair list (docs/contact.md "Neighbour list"): every pair
/// of particles of two trees, or of one tree with itself, closer than
/// r_a + r_b + skin at the build (found by the tree search with every sphere
/// grown by skin / 2), as (min, max). Valid while no tree particle has moved
/// more than skin / 2 from its position at the build (nor changed its radius):
/// then every touching pair of the tree search is in it, and each evaluation
/// tests only those.
struct TreePairList {
  /// The ContactScratch::revision it was built for; -1: none.
  std::int64_t revision = -1;
  double skin = 0.0;          // (m)
  double skinFraction = 0.0;  // ContactSettings::neighbourSkin at the build (-)
  /// Positions and radii of ContactScratch::treeParticles at the build.
  std::vector<Vec3> reference;
  std::vector<double> referenceRadius;
  std::vector<std::array<std::int32_t, 2>> pairs;
  /// Builds so far (the first one included).
  std::int64_t builds = 0;
};

/// A contact the detection found, in Contact::key() order: a bare particle
/// pair (full = -1: the contact (a, other) with every other field at its
/// default), or one found with its geometry: ContactScratch::detectedContacts[full]
/// (full >= 0) or ContactScratch::treeContacts[-2 - full] (full <= -2). The
/// contact stage builds the Contact from it, once.
struct ContactSeed {
  Contact::Key key;
  std::int32_t full = -1;
  static ContactSeed pair(std::int32_t a, std::int32_t other) {
    return {{(static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
                 static_cast<std::uint32_t>(other),
             0, 0},
            -1};
  }
  static ContactSeed found(const Contact& c, std::int32_t full) { return {c.key(), full}; }
  std::int32_t a() const { return static_cast<std::int32_t>(key.pair >> 32); }
  std::int32_t other() const { return static_cast<std::int32_t>(key.pair & 0xFFFFFFFFu); }
};

/// A chunk of the grid particles' detection (contact_detection.cpp), worked on
/// one thread: its rows of the neighbour list when it is rebuilt, its finds, and
/// its tests. The chunks are joined in order (the same list for any thread count).
struct GridChunk {
  std::vector<std::int32_t> partners;  // its rows' partners, row after row
  std::vector<std::int32_t> rowEnds;   // the end of each row's partners in `partners`
  std::vector<std::int32_t> row;       // one particle's partners, to sort
  /// Its particles' finds, in order: seeds[0, seedCount). (The vector keeps its
  /// largest size: a row's candidates are written over old entries, not
  /// constructed first.)
  std::vector<ContactSeed> seeds;
  std::size_t seedCount = 0;
  std::vector<Contact> found;  // its environment contacts (seeds' `full` index them)
  Contact probe;               // a particle's test against an item
  std::int64_t pairTests = 0, environmentTests = 0;
};

/// The rotation of the LS neighbourhood of each particle in a contact that turns
/// with it (contact_force.cpp, MODEL §3.3 rolling), taken once per evaluation
/// rather than once per contact side: slot[i] indexes omega, inverse (6 each, A⁺
/// packed) and largest (A⁺'s largest eigenvalue), or is -1.
struct TurningCache {
  std::vector<std::int32_t> slot;       // (particles)
  std::vector<std::int32_t> particles;  // those with a slot, in slot order
  std::vector<Vec3> omega;
  std::vector<double> inverse, largest;
};

/// What one contact evaluation works in: derived from positions, reused from
/// evaluation to evaluation.
struct ContactScratch {
  /// The tables in use (set by prepareContactScratch for each evaluation).
  const ContactTables* tables = nullptr;
  /// The CompiledModel::contactRevision the trees were built for; -1: none yet.
  std::int64_t revision = -1;
  /// Per particle, the stiffness (N/m) and damping (N·s/m) of its touching
  /// contacts (law::Rates::add), summed during the contact stage for its
  /// stability limit and zeroed again after it, (particleCount).
  std::vector<law::Rates> contactRateSum;
  /// The tree objects with their node ranges, their nodes and permuted particles.
  std::vector<TreeObject> trees;
  std::vector<TreeNode> nodes;
  std::vector<std::int32_t> treeParticles;

  // ---- Per-step scratch.
  std::vector<std::int64_t> cellOfItem;      // (gridParticles) cell id
  std::vector<std::int32_t> cellStart;       // (cells + 1) or (hash buckets + 1)
  std::vector<std::int32_t> sortedItem;      // (gridParticles) position in gridParticles
  std::vector<std::int64_t> sortedCell;      // (gridParticles) cell id, for hash mode
  std::vector<double> sortedData;            // (4 × gridParticles) x, y, z, r
  std::vector<std::int32_t> sortedParticle;  // (gridParticles)
  std::vector<std::int64_t> sortedKey;       // (gridParticles) cell key of each slot
  std::vector<std::int32_t> sweepOrder;      // (trees) sort-and-sweep order
  NeighbourList neighbours;
  TreePairList treePairs;
  std::vector<GridChunk> gridChunks;
  std::vector<ContactSeed> seeds;         // the detection's finds, sorted by key
  std::vector<ContactSeed> mergedSeeds;   // merge buffer
  std::vector<Contact> detectedContacts;  // grid particles' environment contacts
  std::vector<Contact> treeContacts;      // finds of the tree search (sorted after it)
  std::vector<Contact> freshContacts;     // the new list, swapped into the evaluation
  /// Per contact: the trial tangential forces of the friction law, and per
  /// contact group (object pair) the sums the stick/slip decision needs.
  struct FrictionTrial {
    Vec3 elastic, damper;  // -k_t δ_t and -c_t V (N)
    Vec3 relative;         // p_a - p_b or p_a (m)
    Vec3 delta;            // δ_t (m)
    Vec3 armA, armB;       // particle centre to contact point (m)
    /// How each side turns (MODEL §3.3 rolling): 0 not at all, 1 its own spin,
    /// 2 with its LS neighbours, whose rotation inverse (A⁺, packed xx yy zz xy
    /// xz yz, 1/(kg·m²)) carries the friction moment.
    std::int32_t turnA = 0, turnB = 0;
    double inverseA[6]{}, inverseB[6]{};
    double tangentialStiffness = 0.0, tangentialDamping = 0.0;
    double kineticFriction = 0.0;   // μ_k of the pair (-)
    double staticFriction = 0.0;    // μ_s of the pair (-)
    double stribeckVelocity = 0.0;  // v_S of the pair (m/s)
    /// Rim and ball contacts: their body's motion, in ContactScratch::rings.
    std::int32_t ring = -1;
    double slipSpeed = 0.0, previousEnergy = 0.0;
    std::int32_t group = -1;
    bool slow = false;              // |V| <= stick velocity, or V reversed
    std::int32_t regimeBefore = 0;  // Contact::sliding at the last evaluation
    double giveWayBefore = 0.0;     // Contact::giveWay at the last evaluation (m)
    /// For the sums only a group breaking away needs (FrictionGroup::range,
    /// elasticSpeed, slipBefore), taken when it decides: μ_s F_n (N), the
    /// contact point's inverse effective mass (1/kg), and the slip at the last
    /// evaluation (m/s) when the contact persists (hadBefore).
    double frictionLoad = 0.0, tangentialInverse = 0.0;
    Vec3 slipBefore;
    bool hadBefore = false;
  };
  struct FrictionGroup {
    std::int64_t other = 0;
    double normal = 0.0;   // μ_s Σ F_n (N)
    double total = 0.0;    // Σ |k_t δ_t + c_t V| (N)
    double giveWay = 0.0;  // Σ of the anchors' give-way so far (m)
    /// Σ |V| now and at the last evaluation (m/s). slipBefore, range and
    /// elasticSpeed are summed only for a group that was breaking away and
    /// is loaded above μ_s Σ F_n (decideGroups: the only one that reads them).
    double slip = 0.0, slipBefore = 0.0;
    double range = 0.0;  // Σ μ_s F_n / k_t, the anchors' elastic range (m)
    double elasticSpeed =
        0.0;  // Σ μ_s F_n / √(k_t m_eff): an anchor's speed within its range (m/s)
    bool wasSliding = false, wasBreakingAway = false, allSlow = true;
    std::int32_t regime = 0;  // Contact::sliding for every contact of the group
    double scale = 1.0;       // breaking away: μ_s Σ F_n / Σ|F_t|
  };
  /// Per deferred contact (one that loads more than its two particles: a facet,
  /// a rim, or a side turning with its LS neighbourhood), what the serial pass
  /// needs to apply its loads in contact order once its run has decided: where
  /// they act and how each side turns.
  struct FrictionApplication {
    static constexpr std::int8_t kNone = 0, kParticles = 1, kFacet = 2, kRing = 3;
    Vec3 force;                   // friction force on a (N), Contact::frictionForce
    Vec3 normal;                  // normal force on a (N)
    Vec3 rollMoment;              // rolling resistance moment on a (N·m)
    Vec3 armA, armB;              // particle centre to contact point (m)
    double squeeze = 0.0;         // rims: the radial load S (N)
    law::Rates rates;             // its stability rates (N/m, N·s/m), and a facet
    double facetStiffness = 0.0;  // vertex's extra stiffness on a (N/m)
    bool rolling = false;         // rollMoment applies (μ_r > 0)
    std::int32_t ring = -1;       // index into its chunk's rings, or -1
    /// Index of its A⁺ pair (12 doubles: a's, then the other's) in its chunk's
    /// inverses when a side turns with its neighbourhood, else -1.
    std::int32_t inverse = -1;
    std::int8_t kind = kNone, turnA = 0, turnB = 0;
  };
  /// Per contact: what a contact between two particles (or one and the
  /// environment) adds to them, for the gather by particle (contact_force.cpp):
  /// `force` on a and -force on other, the moments on their spins, and the
  /// stability rates each of them gets; nothing for a deferred contact.
  struct ContactLoad {
    Vec3 force, torqueA, torqueB;
    law::Rates rates;
    std::int32_t a = -1, other = -1;  // Contact::a, Contact::other
    bool deferred = false;
  };
  /// A chunk of consecutive contacts, cut where a's object changes so that its
  /// friction runs are whole, worked on one thread: its runs' scratch, its
  /// deferred contacts and its sums (added in chunk order: the same bits for
  /// any thread count).
  struct ContactChunk {
    std::size_t begin = 0, end = 0;                // its contacts
    std::size_t historyBegin = 0, historyEnd = 0;  // the history contacts it carries or releases
    /// The trials of the current run (a's object's contacts, decided together).
    std::vector<FrictionTrial> trials;
    /// When the stage adds the loads as it goes (one thread, no deferred
    /// contacts possible), the current run's loads, as `trials`.
    std::vector<ContactLoad> runLoads;
    /// When, besides, every group is one contact (ContactTables::
    /// singleParticleBodies), each contact decides as it is found: what it adds
    /// to the stage's sums, added in contact order when its run ends.
    struct RunTerms {
      double released = 0.0;      // anchor energy released (J)
      double dissipated = 0.0;    // power dissipated by friction (W)
      double anchorEnergy = 0.0;  // ½ k_t |δ_t|² of its anchor (J)
    };
    std::vector<RunTerms> runTerms;
    std::vector<FrictionGroup> groups;
    /// The rigid motion of each of its rim or ball contacts' bodies.
    std::vector<RingMotion> rings;
    std::vector<double> inverses;
    std::vector<std::int32_t> deferred;  // contact indices, ascending
    double potential = 0.0, dissipativePower = 0.0, releasedEnergy = 0.0;
    ContactStats stats;
  };
  std::vector<ContactChunk> chunks;
  /// Between findContactLoads and applyContactLoads (contact_stage.h): the
  /// chunks in use, the threads the stage's loops take, and whether the chunks
  /// added their loads as they went (StageInput::force).
  std::size_t chunkCount = 0;
  int stageThreads = 1;
  bool direct = false;
  TurningCache turning;
  std::vector<FrictionApplication> applications;  // (contacts), set for deferred ones
  std::vector<ContactLoad> loads;                 // (contacts)
  /// The loads by particle: contacts [aStart[i], aStart[i + 1]) have a = i, and
  /// otherContact[otherStart[i], otherStart[i + 1]) other = i, (particles + 1).
  std::vector<std::int32_t> aStart, otherStart, otherFill, otherContact;
  std::vector<double> chunkSteps;    // per particle chunk of the gather: its smallest step
  std::vector<Vec3> objectCentroid;  // (objects) for viscosity
  std::vector<double> objectMass;    // (objects)
  std::vector<Vec3> vertexPosition;  // (surface vertices) at this evaluation
  /// Per object, the facet margin (m) of its tree (TreeObject::margin), 0 when
  /// unfaceted: added to its node spheres in tests against other objects only.
  std::vector<double> objectMargin;  // (objects)
  /// Facet candidates of the tree search: (probe, object, triangle), probe a
  /// particle index or -1 - vertex; reduced to one contact per (probe, object).
  struct FacetCandidate {
    std::int32_t probe, object, triangle;
  };
  std::vector<FacetCandidate> facetCandidates;
  /// Edge pairs that touch (MODEL §3.8 "Edges"): edge `edge` of the lower
  /// object against edge `otherEdge` of `object`, at s, t along them; reduced
  /// to the deepest per (edge, object).
  struct EdgeCandidate {
    std::int32_t edge, object, otherEdge;
    double s, t, depth, shorter;
    Vec3 normal;
  };
  std::vector<EdgeCandidate> edgeCandidates;
  /// The longest step (s) before a pair of ridges still apart closes past the
  /// onset of an edge contact (edges.h), infinite when none approaches.
  double edgeApproachStep = 0.0;
  /// At this evaluation: each faceted object's triangles' unit normals (the
  /// closest-triangle search and the edges read them), and
  /// per ContactTables::edges whether it is a ridge (convex, and bent: edges.cpp).
  std::vector<Vec3> triangleNormal;  // (surface triangles)
  std::vector<std::int8_t> edgeRidge;
  std::vector<std::int32_t> lowRidges, highRidges;  // a leaf pair's ridges (edges.cpp)
  /// (vertex, other, far end) of both ends of the friction history's edge
  /// contacts, sorted.
  std::vector<std::array<std::int32_t, 3>> edgeHistory;
  ContactStats stats;
};

/// The radius (m) of `node` in a test against another object or the
/// environment: its sphere grown by its object's facet margin (MODEL §3.8).
inline double outerRadius(const ContactScratch& scratch, const TreeNode& node) {
  return node.object >= 0 ? node.radius + scratch.objectMargin[node.object] : node.radius;
}

/// Points the scratch at `tables` and (re)builds its sphere trees from
/// `position` when they were built for another revision of the tables.
/// (The contacts found do not depend on the trees' topology: every candidate
/// pair is tested exactly and the list is sorted.)
ContactScratch& prepareContactScratch(const Model& model, const ContactTables& tables,
                                      std::int64_t revision, const std::vector<Vec3>& position,
                                      ContactScratch& scratch);

/// The parameters of an object pair's override (ContactTables::overrides) when
/// it has one (set into overrideOut), else `table`.
const PairParameters& overriddenPairParameters(const Model& model, const ContactTables& tables,
                                               std::int32_t a, std::int32_t other,
                                               const PairParameters& table,
                                               PairParameters& overrideOut);

/// The combined parameters of particles a and b (or b = -1 - item for the environment).
/// (Inline: the contact stage asks for them once per contact.)
inline const PairParameters& pairParameters(const Model& model, const ContactTables& tables,
                                            std::int32_t a, std::int32_t other,
                                            PairParameters& overrideOut) {
  const std::int32_t materialA = tables.particleMaterial[a];
  const std::int32_t materialB =
      other >= 0 ? tables.particleMaterial[other] : tables.environmentMaterials[-1 - other];
  const PairParameters& table =
      tables.materialPairs[static_cast<std::size_t>(materialA) * tables.materialCount + materialB];
  if (tables.overrides.empty()) return table;
  return overriddenPairParameters(model, tables, a, other, table, overrideOut);
}

/// Whether objects a and b (tree objects) never touch (one ObjectInfo::contactGroup,
/// or Model::noContactPairs).
inline bool objectsExcluded(const ContactTables& tables, std::int32_t a, std::int32_t b) {
  if (!tables.objectContactGroup.empty()) {
    const std::int32_t group = tables.objectContactGroup[static_cast<std::size_t>(a)];
    if (group >= 0 && group == tables.objectContactGroup[static_cast<std::size_t>(b)]) return true;
  }
  if (tables.noContactPairs.empty()) return false;
  const std::array<std::int32_t, 2> key{std::min(a, b), std::max(a, b)};
  return std::binary_search(tables.noContactPairs.begin(), tables.noContactPairs.end(), key);
}

/// Whether particles a and b are carried by one body of a rigid tree: they never
/// touch (their distance cannot change).
inline bool sameRigidBody(const ContactTables& tables, std::int32_t a, std::int32_t b) {
  const std::int32_t body = tables.treeBodyOf[static_cast<std::size_t>(a)];
  return body >= 0 && body == tables.treeBodyOf[static_cast<std::size_t>(b)] &&
         tables.treeOf[static_cast<std::size_t>(a)] == tables.treeOf[static_cast<std::size_t>(b)];
}

/// Whether a connector ties particles a < b.
inline bool excluded(const ContactTables& tables, std::int32_t a, std::int32_t b) {
  const std::int32_t* begin = tables.exclusionPartner.data() + tables.exclusionStart[a];
  const std::int32_t* end = tables.exclusionPartner.data() + tables.exclusionStart[a + 1];
  for (const std::int32_t* p = begin; p != end; ++p) {
    if (*p == b) return true;
    if (*p > b) return false;
  }
  return false;
}

}  // namespace robophi
