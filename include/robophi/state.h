#pragma once
/// \file
/// State: what changes during a step. A plain value: copying it is a snapshot,
/// and restoring the copy undoes a step (used by the adaptive step).

#include <cstdint>
#include <limits>
#include <vector>

#include "robophi/contact.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// The energy account of a state (J). Potentials are measured at the state's
/// positions; `dissipated` is the work removed by dissipative forces since t = 0.
struct EnergyTally {
  double kinetic = 0.0;
  double linearSpring = 0.0;
  double torsionSpring = 0.0;
  double jointSpring = 0.0;
  double gravity = 0.0;
  /// Potential of contacts and of the environment (filled by the contact stage).
  double contact = 0.0;
  /// Work removed so far by damping, friction and viscosity (>= 0 when the
  /// account is right; it only grows).
  double dissipated = 0.0;
  /// Work done on the system from outside (J): by fixed particles moving
  /// kinematically (a moving virtual robot), and between steps by robotics
  /// tasks that add virtual obstacles, change joint targets or disturb an
  /// object (World::bookExternalWork). 0 for a closed system.
  double external = 0.0;

  double potential() const {
    return linearSpring + torsionSpring + jointSpring + gravity + contact;
  }
  /// Mechanical energy E = kinetic + potential.
  double mechanical() const { return kinetic + potential(); }
  /// E + dissipated - external work: constant for an exact integration.
  double total() const { return mechanical() + dissipated - external; }
};

/// The mutable state of a model.
struct State {
  /// Model time t (s).
  double time = 0.0;
  /// Number of steps taken.
  std::int64_t stepCount = 0;
  // Particle arrays, each of Model::particleCount() entries.
  /// p_i (m).
  std::vector<Vec3> position;
  /// v_i (m/s).
  std::vector<Vec3> velocity;
  /// Net force F_i (N) at (position, velocity); valid when forcesValid.
  std::vector<Vec3> force;
  bool forcesValid = false;
  /// Power of the dissipative forces (W, <= 0) at the last force evaluation.
  double dissipativePower = 0.0;
  /// Power (W) put into the system by fixed particles that move kinematically
  /// (a fixed particle keeps its velocity): -Σ F_i·v_i over them, at `force`.
  double drivingPower = 0.0;
  /// The largest stable explicit step (s) of the touching contacts at the last
  /// force evaluation: per particle, Gershgorin on the sum of its contacts'
  /// stiffness and damping (the larger of normal and tangential), as
  /// estimateStability does for connectors; infinite without contacts.
  /// The adaptive step keeps below it (contacts are not in the model's
  /// stability estimate: they come and go).
  double contactCriticalStep = std::numeric_limits<double>::infinity();
  EnergyTally energy;
  /// Touching pairs and environment contacts with their friction anchors, sorted
  /// by Contact::key(), as of the last force evaluation (MODEL §3).
  std::vector<Contact> contacts;
  /// The contact stage's cache (not part of the value: see ContactCacheHolder).
  ContactCacheHolder contactCache;

  /// A state at rest with every particle at the origin, sized for `model`.
  static State sizedFor(const Model& model);
};

/// A 64-bit FNV-1a hash of the bits of time, positions and velocities:
/// equal hashes mean bit-identical states.
std::uint64_t stateHash(const State& state);

}  // namespace robophi
