// A planner-like loop on robophi's installed package: load a scene (or take the
// hand grasp shipped with robophi), step it with the adaptive step, read the
// contacts and the joint values, and set joint targets between steps.
//
//   embed SCENE.json [SECONDS]
//
// Exits 0 when the loop ran to the end with a finite state and every driven
// joint (a servo: stiffness > 0) moved towards its new target; 1 otherwise.
#include <robophi/adaptive_step.h>
#include <robophi/joints.h>
#include <robophi/scene/scene.h>
#include <robophi/version.h>
#include <robophi/world.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE.json [SECONDS]\n", argv[0]);
    return 2;
  }
  const double seconds = argc > 2 ? std::stod(argv[2]) : 1.0;
  robophi::SceneLoadResult loaded = robophi::loadSceneFile(argv[1]);
  if (!loaded.ok()) {
    for (const robophi::Diagnostic& d : loaded.errors) std::fprintf(stderr, "%s\n", d.format().c_str());
    return 2;
  }
  const robophi::Scene& scene = *loaded.scene;
  robophi::World world(scene.model, scene.initial, scene.run.integrator);
  robophi::AdaptiveStepSettings adaptive = scene.run.adaptive;
  adaptive.initialStep = scene.run.dt;  // the scene's dt is the first trial step
  robophi::AdaptiveStepper stepper(world.model(), adaptive);
  const robophi::Model& model = world.model();
  std::printf("robophi %s: '%s', %d particles, %zu joints\n", robophi::kVersion, scene.name.c_str(),
              model.particleCount(), model.joints.size());

  // Plan: every 0.25 s, move each joint's target 0.05 (rad or m) further.
  std::vector<double> start(model.joints.size());
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    start[j] = robophi::jointValue(model, world.state(), j);
  }
  double nextReplan = 0.25;
  std::size_t mostContacts = 0;
  while (world.state().time < seconds) {
    const robophi::AdaptiveStepResult step = stepper.advance(world, seconds - world.state().time);
    if (!step.ok) {
      std::fprintf(stderr, "the step failed: %s\n", step.failure.c_str());
      return 1;
    }
    mostContacts = std::max(mostContacts, world.contacts().size());
    if (world.state().time >= nextReplan) {
      nextReplan += 0.25;
      for (std::size_t j = 0; j < model.joints.size(); ++j) {
        const robophi::JointServo servo = robophi::jointServo(world.model(), j);
        if (servo.hasDrive && servo.stiffness > 0.0) world.setJointTarget(j, servo.target + 0.05);
      }
    }
  }
  const robophi::EnergyTally energy = world.energy();
  std::printf("t = %.3f s in %lld steps; most contacts %zu; energy total %.6g J (external %.3g J)\n",
              world.state().time, static_cast<long long>(world.state().stepCount), mostContacts,
              energy.total(), energy.external);
  int driven = 0, followed = 0;
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const robophi::JointServo servo = robophi::jointServo(world.model(), j);
    if (!servo.hasDrive || servo.stiffness <= 0.0) continue;
    ++driven;
    const double value = robophi::jointValue(world.model(), world.state(), j);
    if (std::isfinite(value) && std::abs(value - servo.target) < std::abs(start[j] - servo.target))
      ++followed;
    std::printf("  %-24s value %.4f, target %.4f (started at %.4f)\n",
                world.model().joints[j].name.c_str(), value, servo.target, start[j]);
  }
  if (!std::isfinite(energy.total())) {
    std::fprintf(stderr, "the state is not finite\n");
    return 1;
  }
  if (followed < driven) {
    std::fprintf(stderr, "%d of %d driven joints moved towards their targets\n", followed, driven);
    return 1;
  }
  std::printf("ok: %d driven joints followed their targets\n", driven);
  return 0;
}
