// The approach bound's floors (approachStepFloor and the whole scene's
// approachStepQuickFloor, MODEL §4.4): never above
// approachStepBound, so that a step for which the floor already clears every
// other limit is the step the bound would have given. Checked along runs of the
// shipped scenes and on random states: objects of fixed and free particles,
// virtual objects, particles of no object, planes, boxes, more than 128
// objects, numbers from 1e-6 to 1e6, and states where every particle is equal.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "integrate/object_box.h"
#include "robophi/adaptive_step.h"
#include "robophi/contact.h"
#include "robophi/scene/scene.h"

namespace robophi {
namespace {

void expectFloorBelowBound(const Model& model, const State& state, const std::vector<Vec3>& force,
                           double fraction, const std::string& where) {
  const double floor = approachStepFloor(model, state, force, fraction);
  const double bound = approachStepBound(model, state, force, fraction);
  ASSERT_FALSE(std::isnan(floor)) << where;
  ASSERT_LE(floor, bound) << where << ": floor " << floor << " above the bound " << bound;
  const double quick = approachStepQuickFloor(model, state, force, fraction);
  ASSERT_FALSE(std::isnan(quick)) << where;
  ASSERT_LE(quick, bound) << where << ": quick floor " << quick << " above the bound " << bound;
}

class ApproachFloorScene : public ::testing::TestWithParam<const char*> {};

TEST_P(ApproachFloorScene, IsNeverAboveTheBoundAlongTheRun) {
  SceneLoadResult loaded = loadSceneFile(std::string(ROBOPHI_SOURCE_DIR "/scenes/") + GetParam());
  ASSERT_TRUE(loaded.ok());
  Scene& scene = *loaded.scene;
  World world(scene.model, scene.initial, Integrator::kVelocityVerlet);
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  int decided = 0;
  for (int k = 0; k < 1500; ++k) {
    const Evaluation& e = world.evaluation();
    for (double fraction : {0.1, 0.5, 3.0})
      expectFloorBelowBound(world.model(), world.state(), e.force, fraction,
                            std::string(GetParam()) + " step " + std::to_string(k));
    decided += approachStepFloor(world.model(), world.state(), e.force, 0.1) > 0.0 ? 1 : 0;
    const AdaptiveStepResult r = stepper.advance(world, 1.0);
    ASSERT_TRUE(r.ok) << r.failure;
  }
  // Not a floor of zero everywhere: it has to clear the other limits to save anything.
  EXPECT_GT(decided, 1000) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Shipped, ApproachFloorScene,
                         ::testing::Values("hand_grasp.json", "wheel_cube_ramp.json",
                                           "arm_obstacle.json", "vehicle_hills.json",
                                           "ball_drop.json", "cloth.json"));

TEST(ApproachFloor, IsNeverAboveTheBoundOnRandomStates) {
  std::mt19937_64 random(20261205);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 9);
  for (int trial = 0; trial < 3000; ++trial) {
    Model model;
    model.gravity = {};
    const int objectCount = trial % 7 == 0 ? 130 + pick(random) : 1 + pick(random) % 5;
    const double scale = std::pow(10.0, pick(random) % 13 - 6);  // 1e-6 .. 1e6
    for (int o = 0; o < objectCount; ++o)
      model.addObject("o" + std::to_string(o), pick(random) == 0 ? "virtual" : "particles");
    const int particles = objectCount + pick(random) * 3;
    for (int i = 0; i < particles; ++i) {
      // Mostly in runs of one object; now and then interleaved, or of no object.
      const int object = i < objectCount ? i : (pick(random) < 7 ? (i * 7) % objectCount : pick(random) % objectCount);
      const ParticleIndex p =
          model.addParticle(1.0 + pick(random), scale * (0.01 + 0.01 * pick(random)),
                            pick(random) < 2, object);
      if (trial % 11 == 0 && pick(random) == 0) model.objectOf[p] = -1;
    }
    if (pick(random) < 5) {
      GroundPlane plane;
      plane.normal = Vec3{unit(random), unit(random), unit(random)};
      plane.normal = plane.normal / norm(plane.normal);
      plane.point = Vec3{unit(random), unit(random), unit(random)} * scale;
      model.environment.planes.push_back(plane);
    }
    if (pick(random) == 0) {
      BoxObstacle box;
      box.halfExtents = {scale, scale, scale};
      model.environment.boxes.push_back(box);
    }
    State state = State::sizedFor(model);
    std::vector<Vec3> force(model.particleCount());
    const bool equal = trial % 13 == 0;  // every particle the same
    const Vec3 offset = Vec3{unit(random), unit(random), unit(random)} * (scale * pick(random));
    for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
      const auto vec = [&](double size) {
        return equal ? Vec3{size, -size, 0.5 * size}
                     : Vec3{unit(random), unit(random), unit(random)} * size;
      };
      state.position[i] = offset + vec(scale);
      state.velocity[i] = vec(scale * std::pow(10.0, pick(random) % 5 - 2));
      force[i] = vec(scale * std::pow(10.0, pick(random) % 5 - 2));
    }
    for (double fraction : {0.1, 0.5})
      expectFloorBelowBound(model, state, force, fraction, "trial " + std::to_string(trial));
  }
}

TEST(ApproachFloor, LeavesNumbersThatAreNotFiniteToTheBound) {
  Model model;
  model.addParticle(1.0, 0.1, false, model.addObject("a", "particles"));
  model.addParticle(1.0, 0.1, false, model.addObject("b", "particles"));
  State state = State::sizedFor(model);
  state.position[1] = {1.0, 0.0, 0.0};
  std::vector<Vec3> force(2);
  force[0].x = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(approachStepFloor(model, state, force, 0.1), 0.0);
  EXPECT_EQ(approachStepQuickFloor(model, state, force, 0.1), 0.0);
  force[0].x = std::numeric_limits<double>::infinity();
  EXPECT_EQ(approachStepFloor(model, state, force, 0.1), 0.0);
  EXPECT_EQ(approachStepQuickFloor(model, state, force, 0.1), 0.0);
}

// The AVX2 box pass and the scalar one give the same boxes (the scalar one is
// what a processor without AVX2 runs): runs of every length from every start,
// into empty boxes and into boxes already holding particles.
TEST(ApproachFloor, TheBoxPassIsTheSameOnAvxAsScalar) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (!detail::haveBoxRunLanes()) GTEST_SKIP() << "no AVX2 here: only the scalar pass runs";
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Model model;
  const int object = model.addObject("o", "particles");
  for (int i = 0; i < 40; ++i) model.addParticle(1.0 + i % 3, 0.01 * (1 + i % 4), i % 5 == 0, object);
  State state = State::sizedFor(model);
  std::vector<Vec3> force(model.particleCount());
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    state.position[i] = {unit(random), unit(random), unit(random)};
    state.velocity[i] = {unit(random) * 10, unit(random), -unit(random)};
    force[i] = {unit(random) * 1e3, unit(random), unit(random) * 1e-3};
  }
  const auto same = [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  for (ParticleIndex begin = 0; begin < model.particleCount(); ++begin) {
    for (ParticleIndex end = begin + 1; end <= model.particleCount(); ++end) {
      for (const bool held : {false, true}) {
        detail::ObjectBox scalar, lanes;
        if (held) {  // a run before this one, into both
          detail::boxRun(model, state, force, 0, 1, scalar);
          detail::boxRun(model, state, force, 0, 1, lanes);
        }
        const double s = detail::boxRun(model, state, force, begin, end, scalar);
        const double l = detail::boxRunLanes(model, state, force, begin, end, lanes);
        ASSERT_TRUE(std::isfinite(s) && std::isfinite(l));
        const std::string where = std::to_string(begin) + ".." + std::to_string(end);
        ASSERT_TRUE(same(scalar.pLow, lanes.pLow) && same(scalar.pHigh, lanes.pHigh)) << where;
        ASSERT_TRUE(same(scalar.vLow, lanes.vLow) && same(scalar.vHigh, lanes.vHigh)) << where;
        ASSERT_TRUE(same(scalar.aLow, lanes.aLow) && same(scalar.aHigh, lanes.aHigh)) << where;
        ASSERT_TRUE(same(scalar.pSum, lanes.pSum)) << where;
        ASSERT_EQ(scalar.count, lanes.count) << where;
        ASSERT_EQ(scalar.smallestRadius, lanes.smallestRadius) << where;
        ASSERT_EQ(scalar.largestRadius, lanes.largestRadius) << where;
        ASSERT_EQ(scalar.anyFree, lanes.anyFree) << where;
      }
    }
  }
  // A NaN anywhere makes both sums not finite.
  force[7].y = std::numeric_limits<double>::quiet_NaN();
  detail::ObjectBox scalar, lanes;
  EXPECT_FALSE(std::isfinite(detail::boxRun(model, state, force, 0, 10, scalar)));
  EXPECT_FALSE(std::isfinite(detail::boxRunLanes(model, state, force, 0, 10, lanes)));
#else
  GTEST_SKIP() << "not an x86-64 build: only the scalar pass exists";
#endif
}

}  // namespace
}  // namespace robophi
