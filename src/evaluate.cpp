// evaluate(): the force evaluation as a pure function of (model, state).
#include "evaluate.h"

#include <stdexcept>

#include "collision/contact_stage.h"
#include "core/text.h"
#include "forces/forces.h"
#include "integrate/integrators.h"
#include "robophi/evaluation.h"

namespace robophi {

Workspace::Workspace() : scratch_(std::make_unique<ContactScratch>()) {}
Workspace::~Workspace() = default;
Workspace::Workspace(const Workspace& other)
    : scratch_(std::make_unique<ContactScratch>()), result_(other.result_) {}
Workspace& Workspace::operator=(const Workspace& other) {
  if (this != &other) result_ = other.result_;  // the scratch stays this workspace's own
  return *this;
}
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

void evaluateForces(const CompiledModel& compiled, const State& state, ContactScratch& scratch,
                    Evaluation& out) {
  const Model& model = compiled.model();
  const std::vector<Vec3>& position = state.position;
  const std::vector<Vec3>& velocity = state.velocity;
  out.force.resize(position.size());
  for (Vec3& f : out.force) f = Vec3{};
  out.torque.resize(position.size());
  for (Vec3& t : out.torque) t = Vec3{};
  EnergyTally& e = out.energy;
  const ForceTally gravity = accumulateGravity(model, position, out.force);
  const ForceTally damping = accumulateLinearDamping(model, velocity, out.force);
  const ForceTally linear = accumulateLinearSprings(model, position, velocity, out.force);
  const ForceTally torsion = accumulateTorsionSprings(model, position, velocity, out.force);
  const ForceTally joint = accumulateJointSprings(model, position, velocity, out.force);
  const ForceTally bodies = accumulateRigidBodies(model, position, velocity, out.force);
  const ForceTally drives = accumulateJointDrives(model, position, velocity, out.force,
                                                  out.jointMotorEffort, out.jointLossEffort);
  e.gravity = gravity.potential;
  e.linearSpring = linear.potential;
  e.torsionSpring = torsion.potential;
  // The body servos' and the rigid bodies' holds count with the joints (MODEL §1.7).
  e.jointSpring = joint.potential + drives.potential + bodies.potential;
  out.dissipativePower = damping.dissipativePower + linear.dissipativePower +
                         torsion.dissipativePower + joint.dissipativePower +
                         bodies.dissipativePower + drives.dissipativePower;
  // MODEL §3: contacts, friction, viscosity (sets e.contact, adds to the power).
  accumulateContacts(model, compiled.contactTables(), compiled.contactRevision(), position,
                     velocity, state.spin, state.frictionHistory, scratch, out);
}

void measureKinetic(const CompiledModel& model, const State& state, Evaluation& out) {
  measureKineticAndDriving(model.model(), model.contactTables().inverseSpinInertia, state, out);
}

const Evaluation& evaluate(const CompiledModel& model, const State& state, Workspace& workspace) {
  const auto n = static_cast<std::size_t>(model.model().particleCount());
  if (state.position.size() != n || state.velocity.size() != n || state.spin.size() > n) {
    throw std::invalid_argument(detail::text(
        "evaluate: the state has {} positions, {} velocities and {} spins; the model has {} "
        "particles",
        state.position.size(), state.velocity.size(), state.spin.size(), n));
  }
  Evaluation& out = workspace.result();
  evaluateForces(model, state, workspace.contactScratch(), out);
  measureKinetic(model, state, out);
  out.energy.dissipated = state.dissipated;
  out.energy.external = state.external;
  return out;
}

}  // namespace robophi
