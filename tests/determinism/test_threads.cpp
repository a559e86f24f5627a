// Threads do not change results: the step's parallel stages (LS gather, the
// per-particle loops, the chunked sums of core/parallel.h, the contact stage's
// chunks and its gather by particle) give one state hash
// for 1, 2, 4 and 8 threads, and the LS gather gives the serial scatter's forces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "collision/contact_test_util.h"
#include "determinism/scene_steps.h"
#include "robophi/connector_forces.h"
#include "robophi/world.h"

namespace robophi {
namespace {

// A hanging cloth of n × n particles (LS along the rows, columns and both
// diagonals), two corners fixed, with per-particle damping: large enough
// (n = 80: 6 400 particles, 25 122 springs) that every stage runs in several chunks.
struct Cloth {
  Model model;
  State initial;
};

Cloth makeCloth(int n) {
  constexpr double kSpacing = 0.01, kStiffness = 1.0e4;  // m, N/m
  Cloth cloth;
  Model& model = cloth.model;
  model.gravity = {0.0, 0.0, -9.81};
  model.contact.enabled = false;
  const int object = model.addObject("cloth", "plate");
  const double mass = 1.0 / (n * n);
  auto index = [n](int i, int j) { return static_cast<ParticleIndex>(j * n + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      model.addParticle(mass, 0.5 * kSpacing, j == 0 && (i == 0 || i == n - 1), object, 1.0e-4);
      // A small out-of-plane ripple, so that the springs stretch unevenly from the start.
      cloth.initial.position.push_back({i * kSpacing, j * kSpacing, 1e-3 * std::sin(0.37 * i + j)});
    }
  }
  const double damping = 0.2 * std::sqrt(kStiffness * mass);
  auto spring = [&](ParticleIndex a, ParticleIndex b, double rest) {
    model.linearSprings.push_back({a, b, rest, kStiffness, damping});
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) spring(index(i, j), index(i + 1, j), kSpacing);
      if (j + 1 < n) spring(index(i, j), index(i, j + 1), kSpacing);
      if (i + 1 < n && j + 1 < n) {
        spring(index(i, j), index(i + 1, j + 1), std::sqrt(2.0) * kSpacing);
        spring(index(i + 1, j), index(i, j + 1), std::sqrt(2.0) * kSpacing);
      }
    }
  }
  cloth.initial.velocity.assign(cloth.initial.position.size(), Vec3{});
  return cloth;
}

std::uint64_t clothHash(const Cloth& cloth, Integrator integrator, int threads, int steps) {
  World world(cloth.model, cloth.initial, integrator);
  world.setThreadCount(threads);
  EXPECT_EQ(world.threadCount(), threads);
  for (int s = 0; s < steps; ++s) EXPECT_EQ(world.step(2.0e-5), StepStatus::kOk);
  return stateHash(world.state());
}

TEST(Threads, ALargeClothEndsWithOneHashOnOneTwoFourAndEightThreads) {
  const Cloth cloth = makeCloth(80);
  for (Integrator integrator :
       {Integrator::kSymplecticEuler, Integrator::kTaylor, Integrator::kVelocityVerlet}) {
    const std::uint64_t one = clothHash(cloth, integrator, 1, 60);
    for (int threads : {2, 4, 8}) {
      EXPECT_EQ(clothHash(cloth, integrator, threads, 60), one)
          << threads << " threads, integrator " << static_cast<int>(integrator);
    }
  }
}

// The same cloth with bending: a TS along every row and column (three
// particles in line, rest angle π) and a JS over every pair of neighbouring
// rows (about the edge (i+1, j)-(i+1, j+1), rest angle as built): 12 480 TS and
// 6 162 JS, above the threshold at which their forces are computed on the
// threads.
Cloth makeBendingCloth(int n) {
  Cloth cloth = makeCloth(n);
  Model& model = cloth.model;
  const std::vector<Vec3>& p = cloth.initial.position;
  auto index = [n](int i, int j) { return static_cast<ParticleIndex>(j * n + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i + 2 < n; ++i) {
      model.torsionSprings.push_back(
          {index(i, j), index(i + 1, j), index(i + 2, j),
           torsionAngle(p[index(i, j)], p[index(i + 1, j)], p[index(i + 2, j)]), 1.0e-3, 1.0e-6});
      model.torsionSprings.push_back(
          {index(j, i), index(j, i + 1), index(j, i + 2),
           torsionAngle(p[index(j, i)], p[index(j, i + 1)], p[index(j, i + 2)]), 1.0e-3, 1.0e-6});
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 2 < n; ++i) {
      const ParticleIndex a = index(i, j), c = index(i + 1, j), b = index(i + 2, j),
                          d = index(i + 1, j + 1);
      model.jointSprings.push_back(
          {a, c, b, d, jointAngle(p[a], p[c], p[b], p[d]), 1.0e-3, 1.0e-6});
    }
  }
  return cloth;
}

TEST(Threads, TorsionAndJointSpringsOnTheThreadsGiveOneHash) {
  const Cloth cloth = makeBendingCloth(80);
  ASSERT_GT(cloth.model.torsionSprings.size(), 3u * 4096u);
  ASSERT_GT(cloth.model.jointSprings.size(), 4096u);
  for (Integrator integrator : {Integrator::kSymplecticEuler, Integrator::kVelocityVerlet}) {
    const std::uint64_t one = clothHash(cloth, integrator, 1, 40);
    for (int threads : {2, 4, 8}) {
      EXPECT_EQ(clothHash(cloth, integrator, threads, 40), one)
          << threads << " threads, integrator " << static_cast<int>(integrator);
    }
  }
}

// The gather adds each particle's springs in ascending order, as the serial
// scatter `F_a += f; F_b -= f` does: the same bits, at any thread count.
TEST(Threads, TheLinearSpringGatherGivesTheSerialScattersForcesBitForBit) {
  Cloth cloth = makeCloth(80);
  // Move the state off rest, so that every spring pulls and damps.
  for (std::size_t i = 0; i < cloth.initial.velocity.size(); ++i) {
    cloth.initial.velocity[i] = {1e-3 * std::cos(0.1 * static_cast<double>(i)), 0.0,
                                 2e-3 * std::sin(0.05 * static_cast<double>(i))};
  }
  const Model& model = cloth.model;
  const std::vector<Vec3>& p = cloth.initial.position;
  const std::vector<Vec3>& v = cloth.initial.velocity;
  // The serial order of evaluateForces: gravity, damping, then LS by spring index.
  std::vector<Vec3> expected(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (model.inverseMass[i] != 0.0) expected[i] += model.gravity * model.mass[i];
    expected[i] -= v[i] * model.linearDamping[i];
  }
  for (const LinearSpring& s : model.linearSprings) {
    const LinearSpringForce f = linearSpringForce(s, p[s.a], p[s.b], v[s.a], v[s.b]);
    expected[s.a] += f.onA;
    expected[s.b] -= f.onA;
  }
  const CompiledModel compiled(model);
  for (int threads : {1, 2, 4, 8}) {
    Workspace workspace;
    workspace.setThreadCount(threads);
    const Evaluation& e = evaluate(compiled, cloth.initial, workspace);
    int differing = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!(e.force[i] == expected[i])) ++differing;
    }
    EXPECT_EQ(differing, 0) << threads << " threads";
  }
}

// The test: three shipped scenes (connectors, contact, friction, a hand
// with its grasp tasks) on 1, 2 and 4 threads end with one state hash.
TEST(Threads, ThreeShippedScenesEndWithOneHashOnOneTwoAndFourThreads) {
  for (const char* name : {"default", "cloth", "hand_grasp"}) {
    const std::string path = std::string(ROBOPHI_SOURCE_DIR "/scenes/") + name + ".json";
    const SceneLoadResult loaded = loadSceneFile(path);
    ASSERT_TRUE(loaded.ok()) << path;
    const RunReport one = testing::runSteps(*loaded.scene, 300, {}, 1);
    EXPECT_TRUE(one.sound()) << path << ": " << one.failure;
    for (int threads : {2, 4}) {
      const RunReport many = testing::runSteps(*loaded.scene, 300, {}, threads);
      EXPECT_EQ(many.stateHash, one.stateHash) << path << ", " << threads << " threads";
      EXPECT_EQ(many.steps, one.steps) << path;
    }
  }
}

// A small model (fewer than 4096 particles) on two threads finds its contacts
// beside its connector stages and adds their loads afterwards (evaluate.cpp),
// timing that against one thread now and then: every evaluation's forces are
// the one-thread forces, bit for bit, with each integrator (the fused pass of
// symplectic Euler and Taylor runs before the two jobs).
TEST(Threads, ASmallModelsContactsFoundBesideItsConnectorsGiveTheOneThreadForces) {
  // The forces, torques and contacts of one evaluation, as bits.
  const auto evaluationBits = [](const World& world) {
    std::vector<std::uint64_t> bits;
    const auto add = [&bits](double x) {
      std::uint64_t b = 0;
      std::memcpy(&b, &x, sizeof b);
      bits.push_back(b);
    };
    for (const Vec3& f : world.forces()) add(f.x), add(f.y), add(f.z);
    for (const Vec3& t : world.evaluation().torque) add(t.x), add(t.y), add(t.z);
    for (const Contact& c : world.contacts()) add(c.normalForce), add(c.frictionForce.x);
    add(world.evaluation().contactCriticalStep);
    add(world.energy().total());
    return bits;
  };
  for (const char* name : {"hand_lift", "wheel_cube_ramp"}) {
    const std::string path = std::string(ROBOPHI_SOURCE_DIR "/scenes/") + name + ".json";
    const SceneLoadResult loaded = loadSceneFile(path);
    ASSERT_TRUE(loaded.ok()) << path;
    for (const Integrator integrator :
         {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler, Integrator::kTaylor}) {
      Scene scene = *loaded.scene;
      scene.run.integrator = integrator;
      ASSERT_LT(scene.model.particleCount(), 4096) << path;
      std::vector<std::vector<std::uint64_t>> one;
      std::size_t touching = 0;  // steps that end with contacts
      const RunReport serial = testing::runSteps(
          scene, 300,
          [&](World& world) {
            one.push_back(evaluationBits(world));
            if (!world.contacts().empty()) ++touching;
          },
          1);
      EXPECT_TRUE(serial.sound()) << path << ": " << serial.failure;
      std::size_t step = 0;
      std::size_t differing = 0;
      const RunReport two = testing::runSteps(
          scene, 300,
          [&](World& world) {
            if (step >= one.size() || evaluationBits(world) != one[step]) ++differing;
            ++step;
          },
          2);
      EXPECT_EQ(step, one.size()) << path;
      EXPECT_EQ(differing, 0u) << path << ", integrator " << static_cast<int>(integrator);
      EXPECT_EQ(two.stateHash, serial.stateHash) << path;
      // Both jobs had work on most steps.
      EXPECT_GT(touching, one.size() / 2) << path;
    }
  }
}

// A dense pile of balls that spin (each its own object, with friction), pressed
// together from the start, and a lattice block among them whose particles turn
// with their LS neighbourhood: enough contacts (about 13 000) that the contact
// stage runs in many chunks on every thread, with both its gathered and its
// deferred (serial) loads.
World makePile(int threads) {
  constexpr int kLayers = 14;
  constexpr double kRadius = 0.005, kSpacing = 0.0098;  // m: neighbours overlap 0.2 mm
  Model model;
  State initial;
  double mass = 0.0;
  const std::int32_t grain = test::addBallPile(model, initial, 18, kLayers, kRadius, kSpacing, mass);
  // A 3 × 3 × 3 block resting on the pile's top layer, its LS along the edges.
  const std::int32_t block = model.addObject("block", "box", grain);
  const auto first = static_cast<ParticleIndex>(initial.position.size());
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        model.addParticle(mass, kRadius, false, block);
        initial.position.push_back({0.05 + i * 2 * kRadius, 0.05 + j * 2 * kRadius,
                                    kRadius + kLayers * kSpacing - 2e-4 + k * 2 * kRadius});
      }
    }
  }
  const auto at = [first](int i, int j, int k) {
    return static_cast<ParticleIndex>(first + (k * 3 + j) * 3 + i);
  };
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) {
        if (i < 2)
          model.linearSprings.push_back({at(i, j, k), at(i + 1, j, k), 2 * kRadius, 2e4, 1.0});
        if (j < 2)
          model.linearSprings.push_back({at(i, j, k), at(i, j + 1, k), 2 * kRadius, 2e4, 1.0});
        if (k < 2)
          model.linearSprings.push_back({at(i, j, k), at(i, j, k + 1), 2 * kRadius, 2e4, 1.0});
      }
    }
  }
  initial.velocity.assign(initial.position.size(), Vec3{});
  World world(model, initial, Integrator::kSymplecticEuler);
  world.setThreadCount(threads);
  return world;
}

TEST(Threads, ADensePileEndsWithOneHashOnOneTwoFourAndEightThreads) {
  std::uint64_t reference = 0;
  std::size_t contacts = 0;
  for (int threads : {1, 2, 4, 8}) {
    World world = makePile(threads);
    for (int s = 0; s < 40; ++s) ASSERT_EQ(world.step(1.0e-5), StepStatus::kOk);
    const std::uint64_t hash = stateHash(world.state());
    if (threads == 1) {
      reference = hash;
      contacts = world.state().frictionHistory.size();
      // Many chunks (of about 512 contacts), and the block's contacts deferred.
      EXPECT_GT(contacts, 8000u);
    } else {
      EXPECT_EQ(hash, reference) << threads << " threads";
      EXPECT_EQ(world.state().frictionHistory.size(), contacts);
    }
  }
}

TEST(Threads, ANegativeThreadCountIsRefusedAndZeroMeansTheCoresAvailable) {
  Workspace workspace;
  EXPECT_THROW(workspace.setThreadCount(-1), std::invalid_argument);
  workspace.setThreadCount(0);
  EXPECT_GE(workspace.threadCount(), 1);
  workspace.setThreadCount(3);
  EXPECT_EQ(workspace.threadCount(), 3);
}

}  // namespace
}  // namespace robophi
