// The energy-based adaptive time step (MODEL §4, docs/adaptive-step.md).
#include "robophi/adaptive_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/text.h"
#include "robophi/connector_forces.h"

namespace robophi {

namespace {

// The energy that can turn into motion: kinetic plus the elastic potentials
// (gravity's potential depends on where the origin is, so it sets no scale).
double activeEnergy(const EnergyTally& e) {
  return e.kinetic + e.linearSpring + e.torsionSpring + e.jointSpring + e.contact;
}

// The energy gravity can release within the scene: Σ m_i |g| × the diagonal of
// the box around the particles. It keeps the scale of a system that starts at
// rest well above the round-off of the energy sums.
double gravityEnergyScale(const Model& model, const State& state) {
  if (state.position.empty()) return 0.0;
  Vec3 low = state.position.front(), high = low;
  double freeMass = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const Vec3& p = state.position[i];
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
    if (!model.isFixed(i)) freeMass += model.mass[i];
  }
  return freeMass * norm(model.gravity) * norm(high - low);
}

}  // namespace

namespace {

// Throws std::invalid_argument naming the first setting out of its range.
const AdaptiveStepSettings& checked(const AdaptiveStepSettings& s) {
  const auto require = [](bool ok, const char* name, double value, const char* range) {
    if (!ok || !std::isfinite(value))
      throw std::invalid_argument(
          detail::text("AdaptiveStepSettings::{} = {} must be {}", name, value, range));
  };
  require(s.initialStep > 0.0, "initialStep", s.initialStep, "> 0 (s)");
  require(s.minStep > 0.0, "minStep", s.minStep, "> 0 (s)");
  require(s.maxStep >= s.minStep, "maxStep", s.maxStep, ">= minStep (s)");
  require(s.energyTolerance > 0.0, "energyTolerance", s.energyTolerance, "> 0");
  require(s.lossToleranceFactor >= 0.0, "lossToleranceFactor", s.lossToleranceFactor, ">= 0");
  require(s.energyFloor > 0.0, "energyFloor", s.energyFloor, "> 0 (J)");
  require(s.shrinkFactor > 0.0 && s.shrinkFactor < 1.0, "shrinkFactor", s.shrinkFactor,
          "in (0, 1)");
  require(s.growFactor >= 1.0, "growFactor", s.growFactor, ">= 1");
  require(s.safety > 0.0 && s.safety <= 1.0, "safety", s.safety, "in (0, 1]");
  require(s.errorOrder >= 0.0, "errorOrder", s.errorOrder, ">= 0 (0: from the integrator)");
  require(s.maxPenetrationFraction >= 0.0, "maxPenetrationFraction", s.maxPenetrationFraction,
          ">= 0");
  require(s.stabilitySafety > 0.0, "stabilitySafety", s.stabilitySafety, "> 0");
  require(s.maxRejectionsInARow >= 1, "maxRejectionsInARow", s.maxRejectionsInARow, ">= 1");
  return s;
}

}  // namespace

AdaptiveStepper::AdaptiveStepper(const Model& model, AdaptiveStepSettings settings)
    : settings_(checked(settings)),
      stabilityLimit_(settings.stabilitySafety * estimateStability(model).criticalStep),
      step_(std::min({settings.initialStep, settings.maxStep, stabilityLimit_})) {
  stats_.smallestStep = std::numeric_limits<double>::infinity();
}

double AdaptiveStepper::proposal(double error) const {
  const double ratio = settings_.energyTolerance / std::max(std::abs(error), 1e-300);
  return settings_.safety * std::pow(ratio, 1.0 / errorOrder_);
}

double AdaptiveStepper::energyError(const EnergyTally& before, const EnergyTally& after) const {
  // MODEL §4.1: error = (ΔE + ΔW_dissipated - ΔW_external) / scale, where
  // W_dissipated is the work of damping, friction and viscosity, W_external that
  // of fixed particles moved kinematically, and the scale is the largest of the
  // active energy before and after, the gravity scale and the floor.
  const double created = (after.mechanical() - before.mechanical()) +
                         (after.dissipated - before.dissipated) -
                         (after.external - before.external);
  const double scale =
      std::max({activeEnergy(before), activeEnergy(after), gravityScale_, settings_.energyFloor});
  return created / scale;
}

AdaptiveStepResult AdaptiveStepper::advance(World& world, double maxDt) {
  AdaptiveStepResult result;
  world.refresh();
  if (!refinedLimit_) {
    // The tighter estimate needs positions: refine at the first step. (Edits
    // that stiffen the model later are not re-estimated: a joint limit that
    // engages and releases every few steps would pay a power iteration each
    // time; the energy test rejects a step that is too large for them.)
    refinedLimit_ = true;
    stabilityLimit_ =
        std::max(stabilityLimit_,
                 settings_.stabilitySafety *
                     estimateStability(world.model(), &world.state().position).criticalStep);
  }
  if (errorOrder_ <= 0.0) {
    errorOrder_ = settings_.errorOrder > 0.0                          ? settings_.errorOrder
                  : world.integrator() == Integrator::kVelocityVerlet ? 3.0
                                                                      : 2.0;
  }
  if (gravityScale_ < 0.0) gravityScale_ = gravityEnergyScale(world.model(), world.state());
  if (!(step_ >= settings_.minStep)) {
    result.ok = false;
    result.failure = detail::text(
        "the adaptive step {:.3g} s is below its floor {:.3g} s before any trial (the "
        "stability estimate allows {:.3g} s): {}",
        step_, settings_.minStep, stabilityLimit_, diagnose(world));
    return result;
  }
  saved_ = world.snapshot();
  const EnergyTally energyBefore = saved_.energy();
  const double penetrationBefore =
      settings_.maxPenetrationFraction > 0.0
          ? deepestPenetrationFraction(world.model(), saved_.evaluation().contacts)
          : 0.0;
  // The touching contacts' own stability limit (they are not in the model's).
  const double contactLimit = settings_.stabilitySafety * saved_.evaluation().contactCriticalStep;
  for (;;) {
    const double dt = std::min({step_, maxDt, contactLimit});
    const StepStatus status = world.step(dt);
    const double error = status == StepStatus::kOk ? energyError(energyBefore, world.energy())
                                                   : std::numeric_limits<double>::infinity();
    // Geometric control (MODEL §4): one step may not push the deepest contact
    // further in by more than the set fraction of a radius. (The depth a soft
    // contact reaches at rest is physics, set by κ_c, and is not capped.)
    const bool tooDeep =
        status == StepStatus::kOk && settings_.maxPenetrationFraction > 0.0 &&
        deepestPenetrationFraction(world.model(), world.contacts()) - penetrationBefore >
            settings_.maxPenetrationFraction;
    const bool accepted = !tooDeep && error <= settings_.energyTolerance &&
                          error >= -settings_.lossToleranceFactor * settings_.energyTolerance;
    if (accepted) {
      result.dt = dt;
      result.energyError = error;
      ++stats_.accepted;
      stats_.smallestStep = std::min(stats_.smallestStep, dt);
      stats_.largestStep = std::max(stats_.largestStep, dt);
      stats_.sumOfSteps += dt;
      stats_.lastEnergyError = error;
      stats_.lastStep = dt;
      // Grow when the error leaves room: δ · safety · (tol/|e|)^(1/p), at most × growFactor.
      step_ = std::min({step_ * std::clamp(proposal(error), 1.0, settings_.growFactor),
                        settings_.maxStep, stabilityLimit_});
      return result;
    }
    // Reject: restore the copy, shrink (at least halve), retry.
    ++stats_.rejected;
    ++result.rejections;
    step_ = dt * std::clamp(tooDeep ? settings_.shrinkFactor : proposal(error), 0.1,
                            settings_.shrinkFactor);
    const bool stalled =
        step_ < settings_.minStep || result.rejections >= settings_.maxRejectionsInARow;
    const std::string why = stalled ? diagnose(world) : std::string();  // the failed trial
    world.restore(saved_);
    if (stalled) {
      result.ok = false;
      result.failure = detail::text(
          "the adaptive step fell to {:.3g} s (floor {:.3g} s) after {} rejections at t = {:.6g} "
          "s: {}",
          step_, settings_.minStep, result.rejections, saved_.state().time, why);
      return result;
    }
  }
}

std::string AdaptiveStepper::diagnose(const World& world) const {
  // Where the trial went wrong: the particle with the largest acceleration and
  // the connector holding the most energy.
  const Model& model = world.model();
  const State& state = world.state();
  const Evaluation& evaluation = world.evaluation();
  ParticleIndex worst = kNoParticle;
  double worstAcceleration = -1.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const double a = norm(evaluation.force[i]) * model.inverseMass[i];
    if (!(a <= worstAcceleration)) {
      worstAcceleration = a;
      worst = i;
    }
  }
  std::string where;
  if (worst != kNoParticle) {
    const auto object = model.objectOf[worst];
    const std::string objectName =
        object >= 0 && object < static_cast<std::int32_t>(model.objects.size())
            ? model.objects[object].name
            : std::string("?");
    where = detail::text("particle {} (object '{}') has the largest acceleration, {:.3g} m/s²",
                         worst, objectName, worstAcceleration);
  }
  double worstEnergy = 0.0;
  std::string connector;
  for (std::size_t k = 0; k < model.linearSprings.size(); ++k) {
    const LinearSpring& s = model.linearSprings[k];
    const double e = linearSpringForce(s, state.position[s.a], state.position[s.b], {}, {}).energy;
    if (e > worstEnergy) {
      worstEnergy = e;
      connector = detail::text("LS {} (particles {}, {}) holds {:.3g} J", k, s.a, s.b, e);
    }
  }
  if (!connector.empty()) where += "; " + connector;
  if (evaluation.energy.contact > 0.0)
    where += detail::text("; contacts hold {:.3g} J", evaluation.energy.contact);
  return where;
}

}  // namespace robophi
