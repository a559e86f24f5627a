#pragma once
// The contact stage of a force evaluation (MODEL §3): find contacts, then apply
// the normal force, friction and viscosity.

#include <cstdint>
#include <vector>

#include "collision/contact_tables.h"
#include "robophi/evaluation.h"
#include "robophi/model.h"

namespace robophi {

/// Finds every contact at `position` into scratch.seeds, sorted by
/// Contact::key(): particle pairs (a < other) and particle-environment contacts
/// (with depth and normal), which the contact stage builds its contacts from.
/// Counts its work in scratch.stats. The grid particles' search runs on up to
/// `threads` threads (the same list for any count). `previous`, the friction
/// history (sorted by key), and the velocities tell an edge contact that goes
/// on or closes from one that would start deep inside a body (edges.h).
void detectContacts(const Model& model, const std::vector<Vec3>& position,
                    const std::vector<Vec3>& velocity, int threads,
                    const std::vector<Contact>& previous, ContactScratch& scratch);

/// The contact stage, in two parts, so that the connector stages can run beside
/// the first (evaluate.cpp); the same bits for any thread count and whether the
/// loads went directly or not.
///
/// findContactLoads, on up to `threads` threads: detects the contacts at
/// (position, velocity, spin: empty or one per particle) and works out their
/// loads into `scratch`, reading only those and `history` (each persisting
/// contact starts from its friction anchor there). With `force` and `torque`
/// (out.force and out.torque, sized) it may add the loads to them as it goes
/// (one thread, nothing deferred); with null it leaves them alone.
///
/// applyContactLoads then adds the contact, friction and viscosity forces to
/// out.force and the spinning particles' torques to out.torque, sets
/// out.energy.contact, adds the dissipative power to out.dissipativePower and sets
/// out.contacts, out.releasedAnchorEnergy (the anchor energy of `history` given
/// up by slipping or opening), out.contactCriticalStep and out.contactStats.
void findContactLoads(const Model& model, const ContactTables& tables, std::int64_t revision,
                      int threads, const std::vector<Vec3>& position,
                      const std::vector<Vec3>& velocity, const std::vector<Vec3>& spin,
                      const std::vector<Contact>& history, ContactScratch& scratch,
                      std::vector<Vec3>* force, std::vector<Vec3>* torque);
void applyContactLoads(const Model& model, const ContactTables& tables,
                       const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                       const std::vector<Vec3>& spin, const std::vector<Contact>& history,
                       ContactScratch& scratch, Evaluation& out);

/// MODEL §3.4 viscosity: -k (V·n) V̂ where V·n >= 0. Returns its power (W, <= 0).
double accumulateViscosity(const Model& model, const std::vector<Vec3>& position,
                           const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                           ContactScratch& scratch);

}  // namespace robophi
