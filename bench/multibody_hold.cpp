// The iiwa holding a pose by joint PD, as rigid bodies (include/robophi/multibody.h):
// robophi's side of ../shared/peers/mujoco/mj_hold.c, the same task and the same
// RESULT line, to run side by side (docs/performance.md "Rigid bodies against MuJoCo").
//
// usage: robophi_multibody_hold URDF dt T kp kd gc(0|1)
//   holds j2 = 1, j4 = −1 (others 0) for T s at step dt by joint PD (kp on the error,
//   kd with the URDF's damping, both implicit), gravity compensated from the library's
//   gravity forces when gc = 1; prints the wall time of the stepping loop and the
//   worst joint error at the end.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

#include "robophi/build/urdf_multibody.h"
#include "robophi/multibody.h"

int main(int argc, char** argv) {
  using namespace robophi;
  using Clock = std::chrono::steady_clock;
  if (argc < 7) {
    std::fprintf(stderr, "usage: %s URDF dt T kp kd gc(0|1)\n", argv[0]);
    return 2;
  }
  const auto t0 = Clock::now();
  build::UrdfMultibody robot;
  try {
    build::UrdfMultibodySpec spec;
    spec.path = argv[1];
    robot = build::makeUrdfMultibody(spec);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s\n", error.what());
    return 2;
  }
  const double dt = std::atof(argv[2]), T = std::atof(argv[3]), kp = std::atof(argv[4]),
               kd = std::atof(argv[5]);
  const bool gc = std::atoi(argv[6]) != 0;
  const Multibody& mb = robot.multibody;
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  std::vector<double> target(n, 0.0);
  if (n > 3) target[1] = 1.0, target[3] = -1.0;
  std::vector<double> q = target, v(n, 0.0), zero(n, 0.0);
  MultibodyInputs inputs;
  inputs.servoStiffness.assign(n, kp);
  inputs.servoDamping.assign(n, kd);
  inputs.servoTarget = target;
  inputs.effort.assign(n, 0.0);
  MultibodyWorkspace ws;
  MultibodyKinematics gravityKinematics;
  const Vec3 gravity{0, 0, -9.81};
  const long steps = std::lround(T / dt);
  const auto t1 = Clock::now();
  for (long s = 0; s < steps; ++s) {
    if (gc) {
      updateKinematics(mb, q.data(), gravityKinematics);
      updateVelocities(mb, zero.data(), gravityKinematics);
      inverseDynamics(mb, gravityKinematics, nullptr, gravity, nullptr, inputs.effort.data());
    }
    stepMultibody(mb, q, v, inputs, dt, gravity, ws);
  }
  const auto t2 = Clock::now();
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(q[i] - target[i]));
  const double loop = std::chrono::duration<double>(t2 - t1).count();
  std::printf(
      "RESULT robophi_hold dt=%g T=%g kp=%g kd=%g gc=%d steps=%ld loop_s=%.4f process_s=%.4f "
      "wall_per_sim_s=%.4f max_joint_err_rad=%.3e q2=%.6f q4=%.6f\n",
      dt, T, kp, kd, gc ? 1 : 0, steps, loop, std::chrono::duration<double>(t2 - t0).count(),
      loop / T, worst, n > 1 ? q[1] : 0.0, n > 3 ? q[3] : 0.0);
  return std::isfinite(worst) ? 0 : 3;
}
