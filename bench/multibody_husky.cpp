// The Husky driving on a plane as rigid bodies: robophi's side of
// ../shared/peers/mujoco/mj_husky.c, the same task (4 wheel velocity servos, gain 100
// N·m·s/rad, ±15 N·m, 4 rad/s, free base) and the same RESULT line, to run side by
// side (docs/performance.md "Rigid bodies against MuJoCo").
//
// usage: robophi_multibody_husky HUSKY_URDF dt T [adaptive(0|1)]
//   dt: the constant step (s), or the adaptive step's largest with adaptive = 1.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "robophi/adaptive_step.h"
#include "robophi/scene/scene.h"
#include "robophi/world.h"

int main(int argc, char** argv) {
  using namespace robophi;
  using Clock = std::chrono::steady_clock;
  if (argc < 4) {
    std::fprintf(stderr, "usage: %s HUSKY_URDF dt T [adaptive(0|1)]\n", argv[0]);
    return 2;
  }
  const auto t0 = Clock::now();
  const double dt = std::atof(argv[2]), T = std::atof(argv[3]);
  const bool adaptive = argc > 4 && std::atoi(argv[4]) != 0;
  UrdfSceneOptions options;
  options.rigid = true;
  options.fixedBase = false;
  SceneLoadResult loaded = loadUrdfFile(argv[1], options);
  if (!loaded.ok()) {
    for (const Diagnostic& d : loaded.errors) std::fprintf(stderr, "%s\n", d.format().c_str());
    return 2;
  }
  Scene& scene = *loaded.scene;
  Multibody& mb = scene.model.rigidTrees[0].multibody;
  // The wheels' velocity servos through the model's joints (a user's calls); every
  // other joint passive, no gravity compensation.
  int wheels = 0;
  for (Joint& joint : scene.model.joints) {
    joint.servoStiffness = joint.servoDamping = 0.0;
    joint.compensateGravity = false;
    if (!joint.inTree() || joint.kind != JointKind::kRevolute || joint.name.find("wheel") == std::string::npos) continue;
    joint.drive.rateGain = 100.0;
    joint.drive.targetRate = 4.0;
    mb.bodies[static_cast<std::size_t>(joint.treeBody)].effortLimit = 15.0;
    ++wheels;
  }
  World world(std::move(scene.model), std::move(scene.initial), Integrator::kSymplecticEuler);
  AdaptiveStepSettings settings;
  settings.maxStep = dt;
  AdaptiveStepper stepper(world.model(), settings);
  const auto base = [&] { return Vec3{world.state().treePositions[0][0], world.state().treePositions[0][1],
                                      world.state().treePositions[0][2]}; };
  const Vec3 start = base();
  double x15 = 0.0, t15 = -1.0;
  long steps = 0;
  const auto t1 = Clock::now();
  while (world.state().time < T - 1e-12) {
    if (adaptive) {
      const AdaptiveStepResult r = stepper.advance(world, T - world.state().time);
      if (!r.ok) {
        std::fprintf(stderr, "stalled: %s\n", r.failure.c_str());
        return 3;
      }
    } else if (world.step(std::min(dt, T - world.state().time)) != StepStatus::kOk) {
      std::fprintf(stderr, "not finite at t = %g s\n", world.state().time);
      return 3;
    }
    ++steps;
    if (t15 < 0.0 && world.state().time >= 1.5 - 1e-9) {
      t15 = world.state().time;
      x15 = base().x;
    }
  }
  const auto t2 = Clock::now();
  const double loop = std::chrono::duration<double>(t2 - t1).count();
  const double wR = 4.0 * 0.17775;  // the wheels' collision cylinder radius (m)
  const Vec3 end = base();
  const double speed = (end.x - x15) / (world.state().time - t15);
  std::printf(
      "RESULT robophi_husky dt=%g T=%g adaptive=%d wheels=%d steps=%ld loop_s=%.4f process_s=%.4f "
      "rtf=%.2f dist_m=%.5f wRT_m=%.5f dist_over_wRT=%.5f speed_1.5_to_end=%.5f speed_over_wR=%.5f "
      "lateral_m=%.2e z=%.4f\n",
      dt, T, adaptive ? 1 : 0, wheels, steps, loop, std::chrono::duration<double>(t2 - t0).count(), T / loop,
      end.x - start.x, wR * T, (end.x - start.x) / (wR * T), speed, speed / wR, end.y - start.y, end.z);
  std::printf("wheel rates (rad/s):");
  for (const MultibodyBody& body : world.model().rigidTrees[0].multibody.bodies)
    if (body.joint == BodyJointKind::kRevolute)
      std::printf(" %.3f", world.state().treeVelocities[0][static_cast<std::size_t>(body.vStart)]);
  std::printf("\n");
  return 0;
}
