#pragma once
// The lean contact stage's contacts four at a time (AVX2): a particle pair's or
// a particle's contact with the environment, its geometry, normal force,
// rolling velocity, slip and friction trial, and, when it sticks (MODEL §3.3: a
// contact alone in its group whose anchor and damper hold within μ_s F_n, and
// that was not sliding), its friction, loads and energy terms. Every lane does
// the operations of the scalar stage (contact_force.cpp, ChunkWalk) in their
// order, without fused multiply-adds: the same bits
// (tests/collision/test_pair_lanes.cpp). The stage adds what the lanes found to
// its sums and loads in contact order; the group of a contact that does not
// stick there decides in the scalar stage's code, from the lanes' trial.

#include <cstddef>

namespace robophi::detail {

/// A batch of up to kSize contacts, one array per quantity (lane l is the
/// batch's l-th contact). The stage fills the inputs; runPairLanes fills the
/// results.
struct PairLaneBatch {
  static constexpr std::size_t kSize = 16;
  // Inputs: the particles' positions and velocities (m, m/s; 0 for the
  // environment's side), the spins of sides that spin on their own (rad/s, else
  // 0), and the persisting contact's anchor (m, when hasBefore is 1) or, when it
  // was sliding (slidBefore 1), the offset its spring holds (-F_t / k_t, m).
  alignas(32) double pax[kSize], pay[kSize], paz[kSize], pbx[kSize], pby[kSize], pbz[kSize];
  alignas(32) double vax[kSize], vay[kSize], vaz[kSize], vbx[kSize], vby[kSize], vbz[kSize];
  alignas(32) double wax[kSize], way[kSize], waz[kSize], wbx[kSize], wby[kSize], wbz[kSize];
  alignas(32) double anchorx[kSize], anchory[kSize], anchorz[kSize], hasBefore[kSize];
  alignas(32) double offsetx[kSize], offsety[kSize], offsetz[kSize], slidBefore[kSize];
  // An environment contact (environment 1): the normal and depth the detection
  // found (m).
  alignas(32) double environment[kSize], foundx[kSize], foundy[kSize], foundz[kSize];
  alignas(32) double foundDepth[kSize];
  // Radii (m), inverse masses (1/kg), inverse spin inertias (1/(kg·m²)) and
  // whether each side spins (1 or 0), and the pair's parameters.
  alignas(32) double ra[kSize], rb[kSize], ima[kSize], imb[kSize];
  alignas(32) double spinInverseA[kSize], spinInverseB[kSize], spinsA[kSize], spinsB[kSize];
  alignas(32) double stiffness[kSize], damping[kSize], tangentialStiffness[kSize];
  alignas(32) double staticFriction[kSize], tangentialDampingRatio[kSize];

  // Results: the geometry (p_a - p_b or p_a, the normal, depth, the arms and
  // their lengths),
  alignas(32) double relx[kSize], rely[kSize], relz[kSize];
  alignas(32) double nx[kSize], ny[kSize], nz[kSize], depth[kSize];
  alignas(32) double armAx[kSize], armAy[kSize], armAz[kSize];
  alignas(32) double armBx[kSize], armBy[kSize], armBz[kSize];
  alignas(32) double armLengthA[kSize], armLengthB[kSize];
  // the normal force F_n, its energy and dissipation terms and its vector,
  alignas(32) double normalForce[kSize], normalPotential[kSize], normalDissipation[kSize];
  alignas(32) double normalx[kSize], normaly[kSize], normalz[kSize];
  // the friction trial (the roll velocity, the slip and its speed, the
  // tangential damping c_t, the contact point's inverse effective mass, δ_t,
  // -k_t δ_t, -c_t V and μ_s F_n) and the stability rates,
  alignas(32) double rollx[kSize], rolly[kSize], rollz[kSize];
  alignas(32) double slipx[kSize], slipy[kSize], slipz[kSize], slipSpeed[kSize];
  alignas(32) double tangentialDamping[kSize], tangentialInverse[kSize];
  alignas(32) double deltax[kSize], deltay[kSize], deltaz[kSize];
  alignas(32) double elasticx[kSize], elasticy[kSize], elasticz[kSize];
  alignas(32) double damperx[kSize], dampery[kSize], damperz[kSize], frictionLoad[kSize];
  alignas(32) double rateStiffness[kSize], rateDamping[kSize];
  // and what a sticking contact writes and adds: the new anchor and its energy,
  // the friction on a, the force on a (normal and friction), the moments on a
  // and b, and the friction's dissipation.
  alignas(32) double newAnchorx[kSize], newAnchory[kSize], newAnchorz[kSize], anchorEnergy[kSize];
  alignas(32) double frictionx[kSize], frictiony[kSize], frictionz[kSize];
  alignas(32) double forcex[kSize], forcey[kSize], forcez[kSize];
  alignas(32) double torqueAx[kSize], torqueAy[kSize], torqueAz[kSize];
  alignas(32) double torqueBx[kSize], torqueBy[kSize], torqueBz[kSize];
  alignas(32) double dissipated[kSize];
  /// Whether the lane's contact sticks: it was not sliding and |F_t| <= μ_s F_n.
  bool sticks[kSize];
  /// The stage's: where the history's contacts with a key not below the lane's
  /// start, and whether the first of them is the lane's contact persisting.
  std::size_t history[kSize];
  bool persists[kSize];
};

/// Whether runPairLanes can run here (AVX2, checked once at run time) and is
/// allowed (allowPairLanes).
bool pairLanesAvailable();

/// Tests: whether the stage may use the lanes (default: yes), to compare its
/// results with and without them.
void allowPairLanes(bool allowed);

/// Lanes [0, count) of `batch` (in fours: up to three lanes past count are
/// worked out from what they hold). Only where pairLanesAvailable().
void runPairLanes(PairLaneBatch& batch, std::size_t count);

}  // namespace robophi::detail
