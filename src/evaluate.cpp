// evaluate(): the force evaluation as a pure function of (model, state).
#include "evaluate.h"

#include <chrono>
#include <stdexcept>

#include "collision/contact_stage.h"
#include "core/parallel.h"
#include "core/text.h"
#include "forces/forces.h"
#include "integrate/integrators.h"
#include "robophi/evaluation.h"

namespace robophi {

Workspace::Workspace()
    : scratch_(std::make_unique<ContactScratch>()),
      forceScratch_(std::make_unique<ForceScratch>()),
      threads_(detail::availableThreads()) {}
Workspace::~Workspace() = default;
Workspace::Workspace(const Workspace& other)
    : scratch_(std::make_unique<ContactScratch>()),
      forceScratch_(std::make_unique<ForceScratch>()),
      threads_(other.threads_),
      result_(other.result_) {}
Workspace& Workspace::operator=(const Workspace& other) {
  if (this != &other) {
    // The scratch stays this workspace's own.
    threads_ = other.threads_;
    result_ = other.result_;
  }
  return *this;
}
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

void Workspace::setThreadCount(int threads) {
  if (threads < 0) {
    throw std::invalid_argument(detail::text(
        "Workspace::setThreadCount: {} threads; give a count >= 1, or 0 for the cores available",
        threads));
  }
  threads_ = threads == 0 ? detail::availableThreads() : threads;
}

namespace {

// A small model (every stage below a parallel loop's minimum) on more than one
// thread: its connector stages run on one thread while its contacts are found
// and their loads worked out on another, and the loads are added afterwards, in
// the order the serial stage adds them (the same bits).
bool contactsBesideConnectors(const Model& model, const State& state, int threads) {
  constexpr auto kSmall = static_cast<std::size_t>(detail::kParallelMinimum);
  const auto n = static_cast<std::size_t>(model.particleCount());
  return threads > 1 && model.contact.enabled && n > 0 && n < kSmall &&
         model.linearSprings.size() < kSmall && model.torsionSprings.size() < kSmall &&
         model.jointSprings.size() < kSmall && state.frictionHistory.size() < kSmall &&
         (!model.linearSprings.empty() || !model.torsionSprings.empty() ||
          !model.jointSprings.empty() || !model.bodies.empty());
}

// Where the two jobs can run (contactsBesideConnectors), whether this evaluation
// runs them: every period times kProbe evaluations on one thread and then kProbe
// beside, and keeps the faster way for the rest of the period (`timed`: this
// evaluation is one of those timed). The first kWarm beside are not timed: the
// worker, idle while one thread worked, may have gone to sleep, and waking it
// would count against beside.
bool chooseBeside(ForceScratch::OverlapChoice& choice, bool& timed) {
  constexpr std::int64_t kPeriod = 4096, kProbe = 64, kWarm = 16;
  const std::int64_t k = choice.evaluations++ % kPeriod;
  if (k == 2 * kProbe + kWarm) {
    choice.beside = choice.besideSeconds <= choice.serialSeconds;
    choice.serialSeconds = choice.besideSeconds = 0.0;
  }
  const bool probing = k < 2 * kProbe + kWarm;
  timed = probing && (k < kProbe || k >= kProbe + kWarm);
  return probing ? k >= kProbe : choice.beside;
}

}  // namespace

void evaluateForces(const CompiledModel& compiled, const State& state, Workspace& workspace,
                    Evaluation& out, FusedParticlePass* pass) {
  const Model& model = compiled.model();
  const int threads = workspace.threadCount();
  const std::vector<Vec3>& position = state.position;
  const std::vector<Vec3>& velocity = state.velocity;
  out.force.resize(position.size());
  out.torque.resize(position.size());
  // At the state's own velocities until a Verlet step measures its kick (World::step).
  out.dissipativeKick = 0.0;
  out.drivingKick = 0.0;
  out.kickStep = 0.0;
  EnergyTally& e = out.energy;
  bool timed = false;
  const bool beside = contactsBesideConnectors(model, state, threads) &&
                      chooseBeside(workspace.forceScratch().overlap, timed);
  const auto began = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  // The connector stages that scale with the model run in parallel, and so do
  // the contacts (src/collision/: chunks of contacts, then a gather by particle);
  // TS and JS compute in parallel and add in order; the bodies and the drives (a
  // few per joint) on this thread.
  // With a fused pass, the first stage runs in LS's job, each chunk of particles
  // before the springs that read it; beside the contacts, which read the
  // positions it makes, it runs first as a loop of its own.
  ParticlePrologue prologue;
  ParticleForceTally start;
  if (pass != nullptr) {
    prologue = {&FusedParticlePass::run, pass};
    if (beside) {
      const std::int64_t chunks =
          (static_cast<std::int64_t>(position.size()) + detail::kParallelChunk - 1) /
          detail::kParallelChunk;
      for (std::int64_t c = 0; c < chunks; ++c) prologue.run(prologue.context, c);
    }
  }
  ForceTally linear, torsion, joint, bodies, drives;
  const auto connectors = [&](int stageThreads) {
    if (pass == nullptr) {
      start = startParticleForces(model, stageThreads, position, velocity, out.force, out.torque);
    }
    linear = accumulateLinearSprings(model, compiled.springIncidence(), stageThreads, position,
                                     velocity, out.force, workspace.forceScratch(),
                                     pass != nullptr && !beside ? &prologue : nullptr);
    if (pass != nullptr) start = pass->tally();
    torsion = accumulateTorsionSprings(model, stageThreads, position, velocity, out.force,
                                       workspace.forceScratch());
    joint = accumulateJointSprings(model, stageThreads, position, velocity, out.force,
                                   workspace.forceScratch());
    // MODEL §1.7: every body's rigid motion, once, for shape matching, the links and the drives.
    std::vector<RigidMotion>& motion = workspace.forceScratch().bodyMotion;
    bodyMotions(model, position, velocity, motion);
    bodies = accumulateRigidBodies(model, motion, position, velocity, out.force,
                                   workspace.forceScratch().linkPreload);
    drives = accumulateJointDrives(model, motion, position, velocity, out.force,
                                   out.jointMotorEffort, out.jointLossEffort,
                                   &out.driveDampingRate);
  };
  // MODEL §3: contacts, friction, viscosity (sets e.contact, adds to the power).
  const auto findContacts = [&](int stageThreads, bool direct) {
    findContactLoads(model, compiled.contactTables(), compiled.contactRevision(), stageThreads,
                     position, velocity, state.spin, state.frictionHistory,
                     workspace.contactScratch(), direct ? &out.force : nullptr,
                     direct ? &out.torque : nullptr);
  };
  if (beside) {
    // Two jobs: the contacts (the larger, taken first by this thread), the connectors.
    detail::runBoth(
        2, [&] { findContacts(1, false); }, [&] { connectors(1); });
  } else {
    connectors(threads);
    findContacts(threads, true);
  }
  const ForceTally& gravity = start.gravity;
  const ForceTally& damping = start.damping;
  e.gravity = gravity.potential;
  e.linearSpring = linear.potential;
  e.torsionSpring = torsion.potential;
  // The body servos' and the rigid bodies' holds count with the joints (MODEL §1.7).
  e.jointSpring = joint.potential + drives.potential + bodies.potential;
  out.dissipativePower = damping.dissipativePower + linear.dissipativePower +
                         torsion.dissipativePower + joint.dissipativePower +
                         bodies.dissipativePower + drives.dissipativePower;
  applyContactLoads(model, compiled.contactTables(), position, velocity, state.spin,
                    state.frictionHistory, workspace.contactScratch(), out);
  if (timed) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    ForceScratch::OverlapChoice& choice = workspace.forceScratch().overlap;
    (beside ? choice.besideSeconds : choice.serialSeconds) += seconds;
  }
}

void measureKinetic(const CompiledModel& model, const State& state, Workspace& workspace,
                    Evaluation& out, const ParticlePassSums* pass) {
  // The bodies' motions of evaluateForces at these positions, at the state's velocities.
  std::vector<RigidMotion>& motion = workspace.forceScratch().bodyMotion;
  if (motion.size() != model.model().bodies.size())
    bodyMotions(model.model(), state.position, state.velocity, motion);
  else
    updateBodyVelocities(model.model(), state.position, state.velocity, motion);
  measureKineticAndDriving(model.model(), model.contactTables().inverseSpinInertia,
                           workspace.threadCount(), motion, state, out, pass);
  // MODEL §1.7: the body links' weight preloads are driving work, as the motors' are.
  const std::vector<std::array<Vec3, 2>>& preload = workspace.forceScratch().linkPreload;
  if (preload.size() == model.model().bodyLinks.size() && !preload.empty())
    if (const double power = bodyLinkPreloadPower(model.model(), motion, preload); power != 0.0)
      out.drivingPower += power;
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
  evaluateForces(model, state, workspace, out);
  measureKinetic(model, state, workspace, out);
  out.energy.dissipated = state.dissipated;
  out.energy.external = state.external;
  return out;
}

}  // namespace robophi
