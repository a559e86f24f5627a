#include "study_ats.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>

#include "robophi/adaptive_step.h"
#include "robophi/contact.h"
#include "robophi/scene/scene.h"
#include "run/interrupt.h"

namespace robophi::cli {

namespace {

constexpr double kGravity = 9.81;

// SIGINT or SIGTERM under robophi study's InterruptGuard: runs stop early, and
// the command writes nothing.
bool interrupted() { return InterruptGuard::flag().load(std::memory_order_relaxed); }

// Case 1: a rigid ball (one particle, 1 kg, r = 5 cm) dropped from 1 m onto the
// ground, κ_c = 1e7 or 1e9 N/m, no damping: it must rebound to exactly 1 m. The error
// is the rebound height implied by the state just after the ball leaves the
// ground, z + v²/(2g), against the drop height.
StudyCase ballDrop(double contactStiffness) {
  struct Observer {
    bool touched = false;
    bool measured = false;
    double reboundHeight = 0.0;
  };
  auto obs = std::make_shared<Observer>();
  constexpr double kRadius = 0.05, kHeight = 1.0;
  StudyCase c;
  c.name = fmt::format("ball drop, kc = {:.0e} N/m", contactStiffness);
  c.errorMeasure = "rebound height (m)";
  c.duration = 0.5;
  c.make = [contactStiffness] {
    Model model;
    model.gravity = {0.0, 0.0, -kGravity};
    const int object = model.addObject("ball", "particles");
    model.addParticle(1.0, kRadius, false, object);
    model.environment.planes.push_back(GroundPlane{});
    model.contact.pairOverrides.push_back(
        ContactPairOverride{0, -1, contactStiffness, 0.0, 0.0, 0.0});
    State state = State::sizedFor(model);
    state.position[0] = {0.0, 0.0, kHeight + kRadius};
    return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
  };
  c.reset = [obs] { *obs = Observer{}; };
  c.observe = [obs](const World& world) {
    const Vec3& p = world.state().position[0];
    const Vec3& v = world.state().velocity[0];
    const double bottom = p.z - kRadius;
    if (bottom < 0.0) obs->touched = true;
    if (obs->touched && !obs->measured && bottom >= 0.0 && v.z > 0.0) {
      obs->measured = true;
      obs->reboundHeight = bottom + v.z * v.z / (2.0 * kGravity);
    }
  };
  c.error = [obs](const World&) {
    return obs->measured ? std::abs(obs->reboundHeight - kHeight) : kHeight;
  };
  return c;
}

// Case 2: a particle of 1 kg on an LS of κ = 1e4 N/m to a fixed anchor
// (ω = 100 rad/s), released 1 cm from rest; 2 s (about 32 periods). The error is
// |x(T) - x_exact(T)| / A with x_exact = A e^(-ζωt) (cos ω_d t + ζ/√(1-ζ²) sin ω_d t).
StudyCase oscillator(double zeta) {
  constexpr double kStiffness = 1.0e4, kMass = 1.0, kAmplitude = 0.01, kDuration = 2.0;
  StudyCase c;
  c.name = zeta == 0.0 ? "oscillator, undamped" : "oscillator, damped (zeta = 0.05)";
  c.errorMeasure = "position at t = 2 s / amplitude";
  c.duration = kDuration;
  c.make = [zeta] {
    Model model;
    model.gravity = {};
    const int object = model.addObject("oscillator", "particles");
    model.addParticle(1.0, 0.01, true, object);
    model.addParticle(kMass, 0.01, false, object);
    const double damping = 2.0 * zeta * std::sqrt(kStiffness * kMass);
    model.linearSprings.push_back({0, 1, 1.0, kStiffness, damping});
    State state = State::sizedFor(model);
    state.position[1] = {1.0 + kAmplitude, 0.0, 0.0};
    return World(std::move(model), std::move(state), Integrator::kVelocityVerlet);
  };
  c.reset = [] {};
  c.observe = [](const World&) {};
  c.error = [zeta](const World& world) {
    const double omega = std::sqrt(kStiffness / kMass);
    const double omegaD = omega * std::sqrt(1.0 - zeta * zeta);
    const double t = world.state().time;
    const double exact =
        kAmplitude * std::exp(-zeta * omega * t) *
        (std::cos(omegaD * t) + zeta / std::sqrt(1.0 - zeta * zeta) * std::sin(omegaD * t));
    return std::abs(world.state().position[1].x - 1.0 - exact) / kAmplitude;
  };
  return c;
}

// A scene given as text (the scene format), for the cases built from generators.
World worldFromScene(const char* text, const char* name) {
  SceneLoadResult loaded = loadSceneText(text, name);
  if (!loaded.ok()) {
    std::string message = std::string(name) + ": ";
    for (const auto& d : loaded.errors) message += d.format() + "\n";
    throw std::runtime_error(message);
  }
  return World(loaded.scene->model, loaded.scene->initial, loaded.scene->run.integrator);
}

// Centre of mass of the particles of one object.
Vec3 objectCentre(const World& world, std::size_t object) {
  const ObjectInfo& info = world.model().objects[object];
  Vec3 sum;
  double mass = 0.0;
  for (ParticleIndex i = info.firstParticle; i < info.firstParticle + info.particleCount; ++i) {
    sum += world.state().position[i] * world.model().mass[i];
    mass += world.model().mass[i];
  }
  return sum / mass;
}

// Cases 3 and 4 have no closed form: their reference is a constant-step run at
// a step far below the others (computed once, then cached).
StudyCase referenceCase(std::string name, std::string measure, double duration,
                        std::function<World()> make, double referenceStep,
                        std::vector<std::size_t> objects) {
  auto reference = std::make_shared<std::vector<Vec3>>();
  StudyCase c;
  c.name = std::move(name);
  c.errorMeasure = std::move(measure);
  c.duration = duration;
  c.make = make;
  c.reset = [] {};
  c.observe = [](const World&) {};
  c.error = [reference, make, referenceStep, duration, objects](const World& world) {
    if (reference->empty()) {
      World ref = make();
      const auto steps = static_cast<std::int64_t>(std::llround(duration / referenceStep));
      for (std::int64_t i = 0; i < steps && !interrupted(); ++i) ref.step(referenceStep);
      for (std::size_t o : objects) reference->push_back(objectCentre(ref, o));
    }
    double worst = 0.0;
    for (std::size_t k = 0; k < objects.size(); ++k) {
      worst = std::max(worst, norm(objectCentre(world, objects[k]) - (*reference)[k]));
    }
    return worst;
  };
  return c;
}

const char* kBarScene = R"({
  "name": "stiff bar falling flat",
  "run": {"integrator": "verlet", "dt": 1e-5},
  "materials": [{"name": "steelish", "contactStiffness": 1e6, "contactDamping": 300,
                 "staticFriction": 0.5, "kineticFriction": 0.4}],
  "environment": {"ground": {"material": "steelish"}},
  "objects": [{"name": "bar", "type": "bar", "center": [0, 0, 0.12], "size": [0.4, 0.04, 0.04],
               "cells": [10, 2, 2], "mass": 1.0, "stiffness": 2e5, "damping": 20,
               "material": "steelish"}]
})";

const char* kWheelCubeScene = R"({
  "name": "wheel and cube on a slope",
  "run": {"integrator": "verlet", "dt": 1e-5},
  "gravity": [1.7, 0, -9.66],
  "materials": [{"name": "rubber", "contactStiffness": 2e5, "contactDamping": 60,
                 "staticFriction": 0.9, "kineticFriction": 0.8}],
  "environment": {"ground": {"material": "rubber"}},
  "objects": [
    {"name": "wheel", "type": "wheel", "center": [0, 0, 0.1], "radius": 0.1, "width": 0.04,
     "axis": [0, 1, 0], "rimParticles": 16, "mass": 1.0, "stiffness": 1e5, "damping": 10,
     "material": "rubber"},
    {"name": "cube", "type": "cube", "center": [0, 0.5, 0.1], "size": 0.2, "cells": 3,
     "mass": 1.0, "stiffness": 1e5, "damping": 10, "material": "rubber"}
  ]
})";

}  // namespace

std::vector<StudyCase> atsStudyCases() {
  std::vector<StudyCase> cases;
  cases.push_back(ballDrop(1.0e7));
  cases.push_back(ballDrop(1.0e9));
  cases.push_back(ballDrop(1.0e10));
  cases.push_back(oscillator(0.0));
  cases.push_back(oscillator(0.05));
  cases.push_back(
      referenceCase("stiff bar falling flat", "centre of mass at t = 0.5 s vs reference (m)", 0.5,
                    [] { return worldFromScene(kBarScene, "<bar study>"); }, 2e-6, {0}));
  cases.push_back(referenceCase(
      "wheel and cube on a 10 degree slope", "centres of mass at t = 1 s vs reference (m)", 1.0,
      [] { return worldFromScene(kWheelCubeScene, "<wheel-cube study>"); }, 2e-6, {0, 1}));
  return cases;
}

namespace {

StudyRun runAdaptive(const StudyCase& c) {
  World world = c.make();
  c.reset();
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  StudyRun run;
  run.mode = "ATS";
  const auto start = std::chrono::steady_clock::now();
  while (world.state().time < c.duration * (1.0 - 1e-12) && !interrupted()) {
    const AdaptiveStepResult r = stepper.advance(world, c.duration - world.state().time);
    if (!r.ok) {
      run.finite = false;
      break;
    }
    c.observe(world);
  }
  run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.steps = stepper.stats().accepted;
  run.rejected = stepper.stats().rejected;
  run.dt = stepper.stats().meanStep();
  run.error = run.finite ? c.error(world) : INFINITY;
  return run;
}

StudyRun runConstant(const StudyCase& c, double dt) {
  World world = c.make();
  c.reset();
  StudyRun run;
  run.mode = "CTS";
  run.dt = dt;
  const auto steps = static_cast<std::int64_t>(std::ceil(c.duration / dt - 1e-9));
  const auto start = std::chrono::steady_clock::now();
  for (std::int64_t i = 0; i < steps && !interrupted(); ++i) {
    if (world.step(dt) != StepStatus::kOk) {
      run.finite = false;
      break;
    }
    c.observe(world);
  }
  run.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.steps = world.state().stepCount;
  run.error = run.finite ? c.error(world) : INFINITY;
  return run;
}

}  // namespace

StudyRow runStudyCase(const StudyCase& c, std::int64_t maxCtsSteps) {
  StudyRow row;
  row.caseName = c.name;
  row.errorMeasure = c.errorMeasure;
  row.ats = runAdaptive(c);
  if (interrupted()) return row;
  c.error(c.make());  // builds a reference solution before any timing of CTS
  const double target = row.ats.error;

  // Halve the constant step from the largest adaptive one until the error is
  // no larger than ATS's, then bisect (in log scale) between the last two.
  double bad = 0.0;
  double dt = std::max(row.ats.dt * 4.0, 1e-6);
  StudyRun good;
  bool found = false;
  while (c.duration / dt <= static_cast<double>(maxCtsSteps)) {
    if (interrupted()) return row;
    StudyRun run = runConstant(c, dt);
    if (run.finite && run.error <= target) {
      good = run;
      found = true;
      break;
    }
    bad = dt;
    dt *= 0.5;
  }
  if (!found) {
    row.ctsBudgetExhausted = true;
    row.cts = runConstant(c, c.duration / static_cast<double>(maxCtsSteps));
  } else {
    if (bad > 0.0) {
      double low = good.dt, high = bad;
      for (int i = 0; i < 6; ++i) {
        const double mid = std::sqrt(low * high);
        StudyRun run = runConstant(c, mid);
        if (run.finite && run.error <= target) {
          good = run;
          low = mid;
        } else {
          high = mid;
        }
      }
    }
    row.cts = good;
  }
  row.stepRatio = static_cast<double>(row.cts.steps) / static_cast<double>(row.ats.steps);
  // Per trial (accepted or rejected) step: the cost of one ATS iteration.
  const double atsTrials = static_cast<double>(row.ats.steps + row.ats.rejected);
  row.costPerStepRatio = (row.ats.wallSeconds / atsTrials) /
                         (row.cts.wallSeconds / static_cast<double>(row.cts.steps));
  return row;
}

}  // namespace robophi::cli
