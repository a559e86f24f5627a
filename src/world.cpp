// World::step: the list of stages of one step (docs/architecture.md), nothing else.
#include "robophi/world.h"

#include <cmath>
#include <stdexcept>

#include "collision/contact_tables.h"
#include "core/parallel.h"
#include "core/text.h"
#include "evaluate.h"
#include "forces/forces.h"
#include "integrate/integrators.h"
#include "integrate/rigid_trees.h"

namespace robophi {

namespace {

// Velocity Verlet (docs/model.md §2.4): the kick power of `evaluation`, just evaluated
// at the state (Evaluation::dissipativeKick, drivingKick); `kickStep` the step whose
// kick follows (0: none, evaluated at the state's velocities).
void measureKickPower(const Model& model, const State& state, Workspace& workspace,
                      Evaluation& evaluation, double kickStep) {
  const PowerKick kick =
      verletKickPower(model, workspace.forceScratch().bodyMotion, state.position, state.velocity,
                      evaluation.force, 1.0, evaluation.jointMotorEffort,
                      evaluation.jointLossEffort, workspace.forceScratch().linkPreload);
  evaluation.dissipativeKick = kick.dissipative;
  evaluation.drivingKick = kick.driving;
  evaluation.kickStep = kickStep;
}

}  // namespace

World::World(Model model, State initial, Integrator integrator)
    : World(CompiledModel(std::move(model)), std::move(initial), integrator) {}

World::World(CompiledModel model, State initial, Integrator integrator)
    : model_(std::move(model)), integrator_(integrator) {
  const auto n = static_cast<std::size_t>(model_.model().particleCount());
  // Spins not given (a state built before spins existed, or particles added after
  // it was sized) are zero.
  if (initial.spin.size() < n) initial.spin.resize(n, Vec3{});
  if (initial.position.size() != n || initial.velocity.size() != n || initial.spin.size() != n) {
    throw std::invalid_argument(detail::text(
        "World: the initial state has {} positions, {} velocities and {} spins; the model has {} "
        "particles",
        initial.position.size(), initial.velocity.size(), initial.spin.size(), n));
  }
  if (const ParticleIndex bad =
          [&] {
            for (std::size_t i = 0; i < n; ++i) {
              if (!isFinite(initial.position[i]) || !isFinite(initial.velocity[i]) ||
                  !isFinite(initial.spin[i]))
                return static_cast<ParticleIndex>(i);
            }
            return kNoParticle;
          }();
      bad != kNoParticle) {
    throw std::invalid_argument(
        detail::text("World: particle {} of the initial state is not finite", bad));
  }
  const std::vector<RigidTree>& trees = model_.model().rigidTrees;
  if (initial.treePositions.size() != trees.size() || initial.treeVelocities.size() != trees.size())
    throw std::invalid_argument(
        detail::text("World: the initial state has {} rigid trees; the model has {}",
                     initial.treePositions.size(), trees.size()));
  for (std::size_t t = 0; t < trees.size(); ++t) {
    const Multibody& mb = trees[t].multibody;
    if (initial.treePositions[t].size() != static_cast<std::size_t>(mb.positionCount) ||
        initial.treeVelocities[t].size() != static_cast<std::size_t>(mb.velocityCount))
      throw std::invalid_argument(
          detail::text("World: rigid tree {} '{}' has {} coordinates and {} rates in the initial "
                       "state, not {} and {}",
                       t, mb.name, initial.treePositions[t].size(),
                       initial.treeVelocities[t].size(), mb.positionCount, mb.velocityCount));
  }
  current_.state_ = std::move(initial);
  if (!trees.empty()) placeTreeParticles(model_.model(), current_.state_, treeWorkspaces_);
}

void World::evaluateCurrent() const {
  State& state = current_.state_;
  Evaluation& evaluation = current_.evaluation_;
  evaluateForces(model_, state, workspace_, evaluation);
  // At the state's own velocities: the next step's first half-kick still moves them.
  if (integrator_ == Integrator::kVelocityVerlet)
    measureKickPower(model_.model(), state, workspace_, evaluation, 0.0);
  measureKinetic(model_, state, workspace_, evaluation);
  if (!model_.model().rigidTrees.empty())
    addRigidTreeTerms(model_.model(), model_.contactTables(), state, evaluation, treeWorkspaces_);
}

void World::refresh() const {
  Snapshot& s = current_;
  if (s.evaluated_) return;
  evaluateCurrent();
  s.evaluated_ = true;
  // The anchors' released energy is dissipated: book this evaluation's in place
  // of the one State::dissipated holds (equal, and 0 added, at an unchanged state).
  s.state_.dissipated += s.evaluation_.releasedAnchorEnergy - s.bookedRelease_;
  s.bookedRelease_ = s.evaluation_.releasedAnchorEnergy;
  if (s.edited_) {
    // What the edits changed in E + dissipated is work done from outside.
    s.edited_ = false;
    const double work = s.energy().total() - s.totalBeforeEdits_;
    s.state_.external += work;
    unreportedWork_ += work;
  }
}

void World::resumeAfterStep(Evaluation evaluation) {
  if (evaluation.force.size() != current_.state_.position.size()) {
    throw std::invalid_argument(
        detail::text("World::resumeAfterStep: an evaluation of {} particles for a model of {}",
                     evaluation.force.size(), current_.state_.position.size()));
  }
  ++changes_;
  Snapshot& s = current_;
  s.evaluation_ = std::move(evaluation);
  s.evaluated_ = true;
  s.edited_ = false;
  s.bookedRelease_ = s.evaluation_.releasedAnchorEnergy;
  unreportedWork_ = 0.0;
}

EnergyTally World::Snapshot::energy() const {
  EnergyTally e = evaluation_.energy;
  e.dissipated = state_.dissipated;
  e.implicitLoss = state_.implicitLoss;
  e.external = state_.external;
  return e;
}

EnergyTally World::energy() const {
  refresh();
  return current_.energy();
}

double World::bookExternalWork() {
  refresh();
  const double work = unreportedWork_;
  unreportedWork_ = 0.0;
  return work;
}

StepStatus World::step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument(detail::text("World::step: dt = {} s must be > 0 and finite", dt));
  }
  ++changes_;
  // 1. Forces at t (cached from the previous step when nothing changed).
  refresh();
  const Model& model = model_.model();
  State& state = current_.state_;
  Evaluation& evaluation = current_.evaluation_;
  const double powerAtStart = evaluation.dissipativePower;
  const double drivingAtStart = evaluation.drivingPower;
  const double dissipativeKickAtStart = evaluation.dissipativeKick;
  const double drivingKickAtStart = evaluation.drivingKick;
  const double kickStepAtStart = evaluation.kickStep;
  // The contacts found at t become the friction history the step starts from
  // (MODEL §3.3); the evaluation at t + δ reads it.
  // Rolling (MODEL §3.3): the anchors turn with the contact points over the step.
  state.frictionHistory.swap(evaluation.contacts);
  const int threads = workspace_.threadCount();
  std::vector<Contact>& history = state.frictionHistory;
  detail::parallelFor(threads, static_cast<std::int64_t>(history.size()),
                      [&](std::int64_t begin, std::int64_t end) {
                        for (auto k = static_cast<std::size_t>(begin);
                             k < static_cast<std::size_t>(end); ++k) {
                          history[k].anchor -= history[k].rollVelocity * dt;
                        }
                      });
  const std::vector<double>& spinInertia = model_.contactTables().inverseSpinInertia;
  // Rigid trees (docs/model.md §7): stepped with the loads at t on their particles,
  // which they then carry to t + δ (the integrators' fixed-particle rule lands them).
  const bool trees = !model.rigidTrees.empty();
  if (trees) stepRigidTrees(model, model_.contactTables(), dt, evaluation, state, treeWorkspaces_);

  // 2. Integrate to t + δ; 3. forces and potentials at t + δ. Taylor's scheme and
  // symplectic Euler leave the velocities final: one pass integrates, starts the
  // evaluation (clear, gravity, damping) and sums the kinetic energy.
  ParticlePassSums* pass = nullptr;
  switch (integrator_) {
    case Integrator::kTaylor:
    case Integrator::kSymplecticEuler:
      if (canIntegrateAndStartForces(model, spinInertia, evaluation, state)) {
        pass = &workspace_.forceScratch().particlePass;
        FusedParticlePass fused = makeFusedParticlePass(
            model, spinInertia, dt, integrator_ == Integrator::kTaylor, evaluation, state, *pass);
        evaluateForces(model_, state, workspace_, evaluation, &fused);
      } else {
        if (integrator_ == Integrator::kTaylor)
          integrateTaylor(model, spinInertia, threads, dt, evaluation, state);
        else
          integrateSymplecticEuler(model, spinInertia, threads, dt, evaluation, state);
        evaluateForces(model_, state, workspace_, evaluation);
      }
      break;
    case Integrator::kVelocityVerlet: {
      integrateVerletDrift(model, spinInertia, threads, dt, evaluation, state);
      evaluateForces(model_, state, workspace_, evaluation);
      // What a kick changes in the power of the forces just evaluated at u.
      measureKickPower(model, state, workspace_, evaluation, dt);
      integrateVerletKick(model, spinInertia, threads, dt, evaluation, state);
      break;
    }
  }

  // 4. Energy account: kinetic at t + δ; the anchors' released energy, the
  // dissipated work and the work of moving fixed particles by the trapezoid rule.
  measureKinetic(model_, state, workspace_, evaluation, pass);
  if (trees)  // (stepRigidTrees left each tree's kinematics at t + δ)
    addRigidTreeTerms(model, model_.contactTables(), state, evaluation, treeWorkspaces_, true);
  state.dissipated += evaluation.releasedAnchorEnergy;
  current_.bookedRelease_ = evaluation.releasedAnchorEnergy;
  if (integrator_ == Integrator::kVelocityVerlet) {
    // docs/model.md §2.4: each force's work as the kicks integrate it. A force F
    // evaluated at velocities u acts in a half-kick u → v = u + δ_k/2 F/m (δ_k the
    // step that evaluated it, 0 for an evaluation at the state) and in the next
    // step's first half-kick v → v + δ/2 F/m; each half-kick's work is δ/2 F·(its
    // velocities' mean). K = Σ F_term·F/m per term (W/s) gives its power at each:
    // P(u + s F/m) = P_u + s K, exactly (the rates are linear in the velocities).
    const double startV = powerAtStart + 0.5 * kickStepAtStart * dissipativeKickAtStart;
    const double endU = evaluation.dissipativePower;
    const double endV = endU + 0.5 * dt * evaluation.dissipativeKick;
    state.dissipated -=
        0.25 * dt * ((2.0 * startV + 0.5 * dt * dissipativeKickAtStart) + (endU + endV));
    // The driving power is measured at the state's velocities v.
    const double drivingEndU = evaluation.drivingPower - 0.5 * dt * evaluation.drivingKick;
    state.external += 0.25 * dt *
                      ((2.0 * drivingAtStart + 0.5 * dt * drivingKickAtStart) +
                       (drivingEndU + evaluation.drivingPower));
  } else {
    state.dissipated -= 0.5 * (powerAtStart + evaluation.dissipativePower) * dt;
    state.external += 0.5 * (drivingAtStart + evaluation.drivingPower) * dt;
  }
  state.time += dt;
  ++state.stepCount;

  // 5. Numerical trouble shows in the energy: one check covers every particle.
  return std::isfinite(current_.energy().total()) ? StepStatus::kOk : StepStatus::kNonFinite;
}

void World::restore(const Snapshot& saved) {
  const auto n = static_cast<std::size_t>(model().particleCount());
  if (saved.state_.position.size() != n || saved.state_.velocity.size() != n ||
      saved.state_.spin.size() != n) {
    throw std::invalid_argument(
        detail::text("World::restore: the snapshot holds {} particles; the model has {}",
                     saved.state_.position.size(), n));
  }
  current_ = saved;
  ++changes_;
}

ParticleIndex World::firstNonFiniteParticle() const {
  const auto n = model().particleCount();
  const State& state = current_.state_;
  for (ParticleIndex i = 0; i < n; ++i) {
    if (!isFinite(state.position[i]) || !isFinite(state.velocity[i]) || !isFinite(state.spin[i]))
      return i;
  }
  return kNoParticle;
}

}  // namespace robophi
