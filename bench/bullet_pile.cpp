// The yardstick of the PILE benchmark: the same pile in Bullet (Debian's
// libbullet-dev, its double-precision build), as issue 16 put it: a
// sweep-and-prune broad phase, a fixed step (1/240 s), Bullet's
// sequential-impulse solver. The balls, box and friction are PILE's
// (apps/robophi/pile_layout.h); the restitution is that of PILE's contact
// damping ratio 0.3. robophi's PILE figure is compared with this program's on
// the same machine, run in turn (docs/performance.md, "PILE against Bullet").
//
// Usage: robophi_bullet_pile [--n N] [--seconds S] [--rate HZ]
//          [--breaking-threshold M] [--iterations K] [--awake]
//   --n: balls per side (default 20: 8000 balls); --seconds: model time
//   (default 1); --rate: steps per second (default 240); --breaking-threshold:
//   Bullet's gContactBreakingThreshold (m; its default 0.02, which also widens
//   every body's box in the broad phase); --iterations: the solver's (default
//   10, Bullet's); --awake: no ball is put to sleep (Bullet's default does).
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "pile_layout.h"

namespace pile = robophi::cli::pile;

int main(int argc, char** argv) {
  int n = 20, iterations = 10;
  double seconds = 1.0, rate = 240.0, threshold = gContactBreakingThreshold;
  bool awake = false;
  for (int k = 1; k < argc; ++k) {
    const bool valued = k + 1 < argc;
    if (std::strcmp(argv[k], "--awake") == 0) {
      awake = true;
    } else if (valued && std::strcmp(argv[k], "--n") == 0) {
      n = std::atoi(argv[++k]);
    } else if (valued && std::strcmp(argv[k], "--seconds") == 0) {
      seconds = std::atof(argv[++k]);
    } else if (valued && std::strcmp(argv[k], "--rate") == 0) {
      rate = std::atof(argv[++k]);
    } else if (valued && std::strcmp(argv[k], "--breaking-threshold") == 0) {
      threshold = std::atof(argv[++k]);
    } else if (valued && std::strcmp(argv[k], "--iterations") == 0) {
      iterations = std::atoi(argv[++k]);
    } else {
      std::fprintf(stderr, "robophi_bullet_pile: unknown option or missing value: %s\n", argv[k]);
      return 2;
    }
  }
  if (n < 1 || !(seconds > 0.0) || !(rate > 0.0) || !(threshold > 0.0) || iterations < 1) {
    std::fprintf(stderr,
                 "robophi_bullet_pile: need --n >= 1, --seconds > 0, --rate > 0, "
                 "--breaking-threshold > 0, --iterations >= 1\n");
    return 2;
  }
  gContactBreakingThreshold = threshold;
  const double step = 1.0 / rate;
  // Bullet multiplies the two bodies' coefficients: each body takes the square
  // root of the pair's. Restitution: a damped spring's, e = exp(-π ζ / √(1 - ζ²)).
  constexpr double kDampingRatio = 0.3;
  const double restitution =
      std::exp(-M_PI * kDampingRatio / std::sqrt(1.0 - kDampingRatio * kDampingRatio));
  const double bodyFriction = std::sqrt(pile::kFriction);
  const double bodyRestitution = std::sqrt(restitution);

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  const double reach = pile::width(n) + 1.0;
  bt32BitAxisSweep3 broadphase(btVector3(-reach, -reach, -1.0),
                               btVector3(reach, reach, pile::kWallHeight + n * pile::kSpacing + 1.0),
                               static_cast<unsigned int>(n * n * n + 16));
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration);
  world.setGravity(btVector3(0.0, 0.0, -9.81));
  world.getSolverInfo().m_numIterations = iterations;

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btDefaultMotionState>> motions;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  const auto addBody = [&](btCollisionShape* shape, double mass, const btVector3& at) {
    btVector3 inertia(0.0, 0.0, 0.0);
    if (mass > 0.0) shape->calculateLocalInertia(mass, inertia);
    motions.push_back(std::make_unique<btDefaultMotionState>(btTransform(btQuaternion::getIdentity(), at)));
    btRigidBody::btRigidBodyConstructionInfo info(mass, motions.back().get(), shape, inertia);
    info.m_friction = bodyFriction;
    info.m_restitution = bodyRestitution;
    bodies.push_back(std::make_unique<btRigidBody>(info));
    if (awake) bodies.back()->setActivationState(DISABLE_DEACTIVATION);
    world.addRigidBody(bodies.back().get());
  };
  shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0.0, 0.0, 1.0), 0.0));
  addBody(shapes.back().get(), 0.0, btVector3(0.0, 0.0, 0.0));
  for (const pile::Wall& wall : pile::walls(n)) {
    shapes.push_back(std::make_unique<btBoxShape>(
        btVector3(wall.halfExtents[0], wall.halfExtents[1], wall.halfExtents[2])));
    addBody(shapes.back().get(), 0.0, btVector3(wall.centre[0], wall.centre[1], wall.centre[2]));
  }
  shapes.push_back(std::make_unique<btSphereShape>(pile::kRadius));
  btCollisionShape* ball = shapes.back().get();
  const double mass = pile::kDensity * 4.0 / 3.0 * M_PI * std::pow(pile::kRadius, 3);
  for (const auto& [x, y, z] : pile::centres(n)) addBody(ball, mass, btVector3(x, y, z));

  // Timed: the steps alone. Between them (not timed), the touching points and
  // the deepest penetration.
  const auto steps = static_cast<long>(std::llround(seconds / step));
  double wall = 0.0, deepest = 0.0, touching = 0.0;
  for (long s = 0; s < steps; ++s) {
    const auto begin = std::chrono::steady_clock::now();
    world.stepSimulation(step, 1, step);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
      for (int k = 0; k < manifold->getNumContacts(); ++k) {
        const double distance = manifold->getContactPoint(k).getDistance();
        if (distance < 0.0) {
          touching += 1.0;
          deepest = std::max(deepest, -distance);
        }
      }
    }
  }
  for (const auto& body : bodies) world.removeRigidBody(body.get());
  std::printf(
      "BULLET-PILE-%d balls=%d steps=%ld step_s=%.6g wall_s=%.3f breaking_threshold_m=%g "
      "iterations=%d sleeping=%s touching_points_per_step=%.1f max_penetration_m=%.3e "
      "(%.1f%% of radius) bullet=%d double=%d\n",
      n * n * n, n * n * n, steps, step, wall, threshold, iterations, awake ? "off" : "on",
      touching / static_cast<double>(steps), deepest, 100.0 * deepest / pile::kRadius,
      btGetVersion(), static_cast<int>(sizeof(btScalar) == sizeof(double)));
  return 0;
}
