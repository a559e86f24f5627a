#pragma once
// The contact stage of computeForces (MODEL §3): find contacts, then apply the
// normal force, friction and viscosity.

#include "collision/contact_cache.h"
#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// Finds every contact at the state's positions into cache.freshContacts,
/// sorted by Contact::key(): particle pairs (a < other) and particle-environment
/// contacts (with depth and normal). Counts its work in cache.stats.
void detectContacts(const Model& model, const State& state, ContactScratch& cache);

/// The contact stage: detects contacts, adds contact, friction and viscosity
/// forces to state.force, sets state.energy.contact, adds the dissipative power
/// to state.dissipativePower and replaces state.contacts (carrying each
/// persisting contact's friction anchor). Energy released by a friction anchor
/// when it slips or opens is added to state.energy.dissipated.
void accumulateContacts(const Model& model, State& state);

/// MODEL §3.4 viscosity: -k (V·n) V̂ where V·n >= 0. Returns its power (W, <= 0).
double accumulateViscosity(const Model& model, State& state, ContactScratch& cache);

}  // namespace robophi
