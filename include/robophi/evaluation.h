#pragma once
/// \file
/// Force evaluation as a pure function (MODEL §1–§3): evaluate(model, state,
/// workspace) computes the net force on every particle, the energy account and
/// the contacts at a state. It reads the state's friction history and never
/// writes the state: calling it any number of times changes nothing. The step
/// (World::step) commits the contacts it finds as the next friction history.

#include <limits>
#include <memory>
#include <vector>

#include "robophi/compiled_model.h"
#include "robophi/contact.h"
#include "robophi/state.h"

namespace robophi {

/// What one evaluation computes at a state.
struct Evaluation {
  /// Net force F_i (N), (particleCount).
  std::vector<Vec3> force;
  /// Net torque τ_i (N·m) on the particles that spin (State::spin), (particleCount);
  /// zero for the others.
  std::vector<Vec3> torque;
  /// Kinetic energy and potentials at the state; dissipated and external as the
  /// state holds them.
  EnergyTally energy;
  /// Power of the dissipative forces (W, <= 0).
  double dissipativePower = 0.0;
  /// Power (W) put into the system from outside: by fixed particles that move
  /// kinematically (a fixed particle keeps its velocity), -Σ F_i·v_i over them,
  /// and by the joints' motors (MODEL §1.6), Σ τ_j q̇_j.
  double drivingPower = 0.0;
  /// Velocity Verlet kicks the velocities the forces were evaluated at by δ/2 F/m
  /// (docs/model.md §2.4): K = Σ F_term·F/m (W/s) of the dissipative forces and of
  /// the driving ones, so that a term's power after a kick of s·F/m is P + s K (the
  /// joints that act through their bodies, the body servos' dampers, the rigid bodies'
  /// dampers and preloads; 0 for the others and for the other integrators); `kickStep`
  /// the step (s) whose second half-kick followed this evaluation, 0 when it was
  /// taken at the state's own velocities.
  double dissipativeKick = 0.0, drivingKick = 0.0, kickStep = 0.0;
  /// Per joint (Model::joints): the effort (N·m or N, positive increases q) of its
  /// motor after the limits, and of its losses (damping and friction), at the
  /// state (MODEL §1.6); 0 for a joint without a drive.
  std::vector<double> jointMotorEffort, jointLossEffort;
  /// Elastic energy (J) the friction anchors of the history gave up in this
  /// evaluation, by slipping or opening: dissipated once the step commits it.
  double releasedAnchorEnergy = 0.0;
  /// The largest stable explicit step (s) of the touching contacts: per
  /// particle, Gershgorin on the sum of its contacts' stiffness and damping;
  /// and no longer than the approach of two faceted bodies' ridges still apart
  /// allows (an edge contact starts at the surface: collision/edges.h);
  /// infinite without contacts. The adaptive step keeps below it.
  double contactCriticalStep = std::numeric_limits<double>::infinity();
  /// A bound on the largest damping rate (1/s) of the joint drives that act
  /// through connector particles (MODEL §1.6: rate gain, damping, friction's
  /// slope); 0 without. The adaptive step adds it to the connectors' damping.
  double driveDampingRate = 0.0;
  /// The contacts at the state, sorted by Contact::key(), with their friction
  /// anchors advanced from the history: the next step's friction history.
  std::vector<Contact> contacts;
  /// Counters of the contact search.
  ContactStats contactStats;
};

struct ContactScratch;
struct ForceScratch;

/// Scratch memory of evaluations (sphere trees, grid, buffers) and the last
/// evaluation. Reusing one workspace keeps evaluations allocation-free; any
/// workspace gives the same results. Not shared between threads.
class Workspace {
 public:
  Workspace();
  ~Workspace();
  /// A copy starts with empty scratch (rebuilt when used) and the same result.
  Workspace(const Workspace& other);
  Workspace& operator=(const Workspace& other);
  Workspace(Workspace&&) noexcept;
  Workspace& operator=(Workspace&&) noexcept;

  /// The last evaluation made in this workspace.
  const Evaluation& result() const { return result_; }
  Evaluation& result() { return result_; }
  ContactScratch& contactScratch() { return *scratch_; }
  ForceScratch& forceScratch() { return *forceScratch_; }

  /// The most threads the evaluation's parallel stages (connector forces, the
  /// per-particle loops and sums) use; 0 (the default) means the cores
  /// available. The results are bit-identical whatever the count. Throws
  /// std::invalid_argument for a negative count.
  void setThreadCount(int threads);
  /// The count in use (>= 1).
  int threadCount() const { return threads_; }

 private:
  std::unique_ptr<ContactScratch> scratch_;
  std::unique_ptr<ForceScratch> forceScratch_;
  int threads_ = 1;
  Evaluation result_;
};

/// Evaluates forces, energies and contacts of `state` (sized for the model;
/// throws std::invalid_argument otherwise) into workspace.result().
const Evaluation& evaluate(const CompiledModel& model, const State& state, Workspace& workspace);

}  // namespace robophi
