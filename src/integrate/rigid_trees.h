#pragma once
// The rigid trees' stage of the step (docs/model.md §7, docs/architecture.md): each
// tree stepped with the loads the evaluation found on its particles, its particles
// moved with its bodies, and its energies in the account.

#include <vector>

#include "collision/contact_tables.h"
#include "robophi/evaluation.h"
#include "robophi/model.h"
#include "robophi/multibody.h"
#include "robophi/state.h"

namespace robophi {

/// Puts every tree particle where its body is at the trees' (q, v): position and
/// velocity (the state as a user or a checkpoint gives it, made consistent).
void placeTreeParticles(const Model& model, State& state, std::vector<MultibodyWorkspace>& scratch);

/// Steps every tree over dt under the force and torque that `evaluation` (at t)
/// found on its particles, gravity and its inputs; then sets each tree particle's
/// velocity to its body's at t + dt and its position to where its body puts it at
/// t + dt less dt times that velocity: the integrators' rule for a fixed particle
/// (p += v dt, in every scheme) then lands it on the body. The trees' dissipated
/// and input work go into state.dissipated and state.external. The pressing contacts
/// between a tree and anything but itself are implicit in the tree's step (their
/// stiffness and damping, model/multibody_contacts.h; docs/model.md §7 "Contacts on
/// rigid trees"), and no longer bound the step.
void stepRigidTrees(const Model& model, const ContactTables& tables, double dt,
                    const Evaluation& evaluation, State& state,
                    std::vector<MultibodyWorkspace>& scratch);

/// The loads an evaluation found on the tree's particles as wrenches on its bodies
/// (spatial forces about the world origin, in W; one per body).
void treeParticleWrenches(const RigidTree& tree, const State& state, const Evaluation& evaluation,
                          std::vector<SpatialVector>& wrench);

/// The tree's accelerations a (velocityCount) at `state` under the loads `evaluation`
/// found on its particles, gravity and its joints' inputs (servos, drives, gravity
/// compensation, damping) taken explicitly at the state: forward dynamics, for
/// observers (sensors); the step itself is not changed. Hard stops and joint
/// friction's stiction are left out. Leaves the tree's kinematics at `state` in
/// ws.kinematics.
void treeAccelerations(const Model& model, std::size_t tree, const State& state,
                       const Evaluation& evaluation, MultibodyWorkspace& ws,
                       std::vector<double>& a);

/// Adds the trees' terms to an evaluation measured at `state`: their kinetic and
/// gravitational energy, their servos' potential (jointSpring), and takes back the
/// driving power booked for their particles as fixed particles (−F·v each): the
/// loads on them act on the trees, whose energy is in the account, not from outside.
/// Lowers the contacts' critical step to each touching body's (docs/model.md §7):
/// ω² = 2 w Σ (κ + k_t) over the body's contacts that its step takes explicitly, w
/// the bound on the body's inverse effective mass at its particles
/// (ContactTables::contactInverseMass); the contact stage leaves tree particles out.
/// kinematicsCurrent: scratch already holds each tree's kinematics at `state` (as
/// stepRigidTrees leaves them), not computed again.
void addRigidTreeTerms(const Model& model, const ContactTables& tables, const State& state,
                       Evaluation& evaluation, std::vector<MultibodyWorkspace>& scratch,
                       bool kinematicsCurrent = false);

}  // namespace robophi
