// robotics::Controller and the scene's "control" section (docs/robots.md
// "Controlling joints"): PD holding an arm against gravity (the steady error is
// τ_g / kp), tracking a sine, velocity and effort modes against their closed
// forms, effort and velocity limits, a mimic joint, sequences whose conditions
// fire at the right time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "robophi/build/goals.h"
#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "robotics/controller.h"
#include "robotics/tasks.h"

namespace robophi {
namespace {

// A scene run step by step with its tasks, as the runner calls them.
struct Sim {
  Scene scene;
  std::optional<World> world;
  robotics::SceneTaskHook hook;
  std::vector<std::string> events;
  explicit Sim(const std::string& text) {
    SceneLoadResult result = loadSceneText(text, "control.json");
    for (const auto& e : result.errors) ADD_FAILURE() << e.format();
    if (!result.ok()) return;
    scene = std::move(*result.scene);
    world.emplace(scene.model, scene.initial, Integrator::kVelocityVerlet);
    hook = robotics::makeSceneTaskHook(scene);
    if (hook.task) hook.task->start(*world, events);
  }
  bool ok() const { return world.has_value(); }
  void step(double dt) {
    world->step(dt);
    if (hook.task) hook.task(*world, events);
    world->bookExternalWork();
  }
  double q(std::size_t j) const { return jointPosition(world->model(), world->state(), j); }
  double rate(std::size_t j) const { return jointRate(world->model(), world->state(), j); }
};

// One link of 0.5 m, 1 kg, horizontal along +x from (0, 0, 1), turning about +y:
// gravity pulls its tool down, which increases q.
std::string arm(const std::string& control, const std::string& gravity = "[0, 0, -9.81]",
                const std::string& links = "[0.5]", const std::string& axes = "[[0, 1, 0]]") {
  return R"({"robophi": 1, "gravity": )" + gravity + R"(,
    "objects": [{"name": "arm", "type": "arm", "base": [0, 0, 1], "direction": [1, 0, 0],
                 "links": )" +
         links + R"(, "axes": )" + axes + R"(, "mass": 1.0}],
    "control": )" +
         control + "}";
}

// About joint j's axis: the free particles' moment of inertia (kg·m²) and the
// gravity torque on them (N·m, positive increases q) at the state.
struct AxisLoad {
  double inertia = 0.0, gravityTorque = 0.0;
};
AxisLoad axisLoad(const Model& model, const State& state, std::size_t j) {
  const JointSpring& s = model.jointSprings[static_cast<std::size_t>(model.joints[j].connector)];
  const Vec3 c = state.position[s.c];
  const Vec3 n = (state.position[s.d] - c) * (1.0 / norm(state.position[s.d] - c));
  AxisLoad out;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (model.isFixed(i)) continue;
    const Vec3 r = state.position[i] - c;
    const Vec3 rPerp = r - n * dot(r, n);
    out.inertia += model.mass[i] * squaredNorm(rPerp);
    out.gravityTorque += dot(cross(r, model.gravity * model.mass[i]), n);
  }
  return out;
}

TEST(Control, PositionServoHoldsTheArmAgainstGravityWithTheClosedFormError) {
  // kp = 100 N·m/rad; τ_g ≈ m g L/2 = 2.45 N·m: the steady error is τ_g / kp ≈ 0.025 rad.
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 100, "kd": 4, "target": 0}}})"));
  ASSERT_TRUE(sim.ok());
  for (int s = 0; s < 15000; ++s) sim.step(2e-4);
  const AxisLoad load = axisLoad(sim.world->model(), sim.world->state(), 0);
  const double expected = load.gravityTorque / 100.0;
  EXPECT_GT(expected, 0.02);
  EXPECT_NEAR(sim.q(0), expected, 0.02 * expected)
      << "q = " << sim.q(0) << " rad, τ_g/kp = " << expected << " rad";
  EXPECT_LT(std::abs(sim.rate(0)), 1e-3);
}

TEST(Control, PositionServoTracksASineWithASmallRmsError) {
  // q* = 0.5 sin(2π t / 2 s), no gravity; kp = 200, kd = 10 and the rate feed-forward kd q̇*.
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 200, "kd": 10,
                 "target": {"sine": {"amplitude": 0.5, "period": 2}}}}})",
              "[0, 0, 0]"));
  ASSERT_TRUE(sim.ok());
  double sum = 0.0, worst = 0.0;
  int count = 0;
  for (int s = 1; s <= 20000; ++s) {
    sim.step(2e-4);
    const double t = sim.world->state().time;
    if (t < 1.0) continue;  // past the start transient
    const double error = sim.q(0) - 0.5 * std::sin(M_PI * t);
    sum += error * error;
    worst = std::max(worst, std::abs(error));
    ++count;
  }
  const double rms = std::sqrt(sum / count);
  // The closed form of the lag: the servo's error I q̈* / kp ≈ 0.08 × 4.9 / 200 = 2e-3 rad at most.
  EXPECT_LT(rms, 3e-3) << "RMS " << rms << " rad, worst " << worst << " rad";
  EXPECT_LT(worst, 5e-3);
}

TEST(Control, VelocityModeReachesTheClosedFormRate) {
  // Rate drive kv = 2 against the joint's damping b = 0.1: q̇ = kv q̇* / (kv + b).
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "velocity", "kv": 2, "target": 1.0,
                 "damping": 0.1}}})",
              "[0, 0, 0]"));
  ASSERT_TRUE(sim.ok());
  for (int s = 0; s < 10000; ++s) sim.step(2e-4);
  const double expected = 2.0 / 2.1;
  EXPECT_NEAR(sim.rate(0), expected, 0.002 * expected) << "q̇ = " << sim.rate(0);
}

TEST(Control, EffortModeAcceleratesAtTauOverI) {
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "effort", "target": 0.2}}})", "[0, 0, 0]"));
  ASSERT_TRUE(sim.ok());
  const AxisLoad load = axisLoad(sim.world->model(), sim.world->state(), 0);
  // The link's turn, read at its tool about the first joint (the JS's own particle
  // b sits near the axis and carries the link's bending): θ = ½ α t².
  const Model& model = sim.world->model();
  const auto tool = static_cast<ParticleIndex>(model.particleCount() - 1);
  const Vec3 c = sim.world->state().position[model.jointSprings[0].c];
  const Vec3 r0 = sim.world->state().position[tool] - c;
  for (int s = 0; s < 2500; ++s) sim.step(2e-4);  // 0.5 s: θ = ½ α t² ≈ 0.19 rad
  const Vec3 r1 = sim.world->state().position[tool] - c;
  const double theta = std::atan2(norm(cross(r0, r1)), dot(r0, r1));
  const double t = sim.world->state().time;
  const double alpha = 2.0 * theta / (t * t);
  EXPECT_NEAR(alpha, 0.2 / load.inertia, 0.01 * 0.2 / load.inertia)
      << "α = " << alpha << ", τ/I = " << 0.2 / load.inertia;
}

// The largest servo pull kp |q* − q| (N·m) and the fastest rate (rad/s) over a run.
struct Extremes {
  double pull = 0.0, rate = 0.0;
};
Extremes runWatching(Sim& sim, int steps) {
  Extremes e;
  for (int s = 0; s < steps; ++s) {
    sim.step(2e-4);
    e.rate = std::max(e.rate, std::abs(sim.rate(0)));
    const JointServo servo = jointServo(sim.world->model(), 0);
    const double q = jointValue(sim.world->model(), sim.world->state(), 0);
    e.pull = std::max(e.pull, servo.stiffness * std::abs(wrapSigned(servo.target - q)));
  }
  return e;
}

TEST(Control, EffortAndVelocityLimitsAreRespected) {
  // A step of the target by 1 rad (no gravity). With effortLimit 1 N·m the servo
  // never pulls harder than 1 N·m, and the joint still arrives.
  Sim limited(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 100, "kd": 2,
                     "target": 1.0, "effortLimit": 1.0}}})",
                  "[0, 0, 0]"));
  ASSERT_TRUE(limited.ok());
  const Extremes a = runWatching(limited, 30000);
  EXPECT_LE(a.pull, 1.0 + 1e-9);
  EXPECT_NEAR(limited.q(0), 1.0, 0.01);
  // With velocityLimit 0.5 rad/s the target moves at 0.5 rad/s and the joint
  // (over-damped servo, kd = 8) never turns faster.
  Sim slow(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 100, "kd": 8,
                  "target": 1.0, "velocityLimit": 0.5}}})",
               "[0, 0, 0]"));
  ASSERT_TRUE(slow.ok());
  const Extremes b = runWatching(slow, 20000);
  EXPECT_LT(b.rate, 0.5 * 1.03) << "fastest " << b.rate << " rad/s";
  EXPECT_GT(b.rate, 0.5 * 0.95);
  EXPECT_NEAR(slow.q(0), 1.0, 0.01);  // arrives after 2 s at 0.5 rad/s, then holds
}

TEST(Control, AMimicJointFollowsItsLeader) {
  // Two links; j2 = −0.5 q1 + 0.1 while j1 follows a sine (no gravity).
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 100, "kd": 4,
                   "target": {"sine": {"amplitude": 0.4, "period": 2}}}},
                 "mimic": [{"joint": "arm.j2", "leader": "arm.j1", "multiplier": -0.5,
                            "offset": 0.1, "kp": 400, "kd": 4}]})",
              "[0, 0, 0]", "[0.5, 0.4]", "[[0, 0, 1], [0, 0, 1]]"));
  ASSERT_TRUE(sim.ok());
  double worst = 0.0;
  for (int s = 1; s <= 15000; ++s) {
    sim.step(2e-4);
    if (sim.world->state().time > 0.5)
      worst = std::max(worst, std::abs(sim.q(1) - (-0.5 * sim.q(0) + 0.1)));
  }
  EXPECT_LT(worst, 5e-3) << "largest mimic error " << worst << " rad";
}

TEST(Control, ASequenceStartsItsPhasesAtTheRightTimes) {
  // Phase "swing" at 0.2 s moves the target to 0.5 rad over 0.5 s (cubic
  // keyframes); "back" starts when the joint is within 0.01 rad of it; "rest" 0.3 s later.
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 200, "kd": 10, "target": 0}},
                 "sequence": [
                   {"name": "swing", "at": 0.2, "joints": {"arm.j1": {"mode": "position",
                     "kp": 200, "kd": 10, "target": {"keyframes": [[0, 0], [0.5, 0.5]],
                                                     "interpolation": "cubic"}}}},
                   {"name": "back", "when": {"jointsAtTarget": {"tolerance": 0.01}},
                    "joints": {"arm.j1": {"mode": "position", "kp": 200, "kd": 10, "target": 0}}},
                   {"name": "rest", "after": 0.3, "joints": {"arm.j1": {"mode": "passive"}}}]})",
              "[0, 0, 0]"));
  ASSERT_TRUE(sim.ok());
  const auto& controller = sim.hook.task;
  ASSERT_TRUE(controller);
  double firstWithin = -1.0;  // when the joint first came within 0.01 rad of 0.5 rad (after 0.7 s)
  for (int s = 0; s < 10000; ++s) {
    sim.step(2e-4);
    const double t = sim.world->state().time;
    if (firstWithin < 0.0 && t > 0.2 && std::abs(sim.q(0) - 0.5) <= 0.01 &&
        std::abs(sim.q(0) - 0.0) > 0.01)
      firstWithin = t;
  }
  const nlohmann::json outcomes = controller->outcomes(*sim.world);
  const auto& phases = outcomes.at("control").at("phases");
  ASSERT_EQ(phases.size(), 3u);
  EXPECT_NEAR(phases[0].at("started_s").get<double>(), 0.2, 2e-4);
  ASSERT_GT(firstWithin, 0.0);
  // The condition fires at the step where it first holds.
  EXPECT_NEAR(phases[1].at("started_s").get<double>(), firstWithin, 1e-9);
  EXPECT_NEAR(phases[2].at("started_s").get<double>(), firstWithin + 0.3, 2e-4);
  EXPECT_EQ(jointServo(sim.world->model(), 0).stiffness, 0.0);  // passive at the end
}

TEST(Control, AContactForceConditionFiresWhenTheBallLands) {
  // A 0.1 kg ball dropped from 0.2 m (its bottom): it lands at sqrt(2 h / g) = 0.2019 s;
  // the phase starts when its contact force with the ground exceeds m g / 2.
  const std::string text = R"({"robophi": 1,
    "objects": [{"name": "ball", "type": "particles", "particles": [
                   {"position": [0, 0, 0.25], "mass": 0.1, "radius": 0.05}]},
                {"name": "arm", "type": "arm", "base": [1, 0, 1], "links": [0.3], "mass": 0.5}],
    "environment": {"ground": true},
    "control": {"sequence": [{"name": "landed",
                "when": {"contactForce": {"object": "ball", "above": 0.49}}}]}})";
  Sim sim(text);
  ASSERT_TRUE(sim.ok());
  for (int s = 0; s < 3000; ++s) sim.step(1e-4);
  const nlohmann::json outcomes = sim.hook.task->outcomes(*sim.world);
  const auto& phase = outcomes.at("control").at("phases").at(0);
  ASSERT_TRUE(phase.at("started").get<bool>()) << outcomes.dump();
  EXPECT_NEAR(phase.at("started_s").get<double>(), std::sqrt(2 * 0.2 / 9.81), 1e-3) << phase.dump();
}

TEST(Control, AMovingBaseTurnsAndTranslatesOnItsKeyframes) {
  // The arm's fixed base turns 90° about +z and rises 5 cm over 1 s (cubic),
  // carrying the servoed link with it.
  Sim sim(arm(R"({"joints": {"arm.j1": {"mode": "position", "kp": 50, "kd": 2, "target": 0}},
                 "bases": [{"object": "arm", "axis": [0, 0, 1], "interpolation": "cubic",
                            "keyframes": [[0, [0, 0, 0], 0], [1, [0, 0, 0.05], 1.5707963267948966]]}]})",
              "[0, 0, 0]", "[0.5]", "[[0, 0, 1]]"));
  ASSERT_TRUE(sim.ok());
  const Model& model = sim.world->model();
  std::vector<ParticleIndex> base;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i)
    if (model.isFixed(i)) base.push_back(i);
  ASSERT_FALSE(base.empty());
  const std::vector<Vec3> expected =
      build::movedPose(sim.scene.initial.position, base, {0, 0, 0.05}, {0, 0, 1}, M_PI / 2);
  for (int s = 0; s < 7500; ++s) sim.step(2e-4);  // 1.5 s: turned, then held
  for (std::size_t k = 0; k < base.size(); ++k) {
    EXPECT_LT(norm(sim.world->state().position[base[k]] - expected[k]), 1e-9) << base[k];
    EXPECT_LT(norm(sim.world->state().velocity[base[k]]), 1e-12);
  }
  // The link turned with its base: the tool, which started along +x, is where the
  // base's rigid motion takes it (the servo holds q = 0 against the turn).
  Vec3 center{};
  for (ParticleIndex i : base) center += sim.scene.initial.position[i];
  center = center / static_cast<double>(base.size());
  const auto tool = static_cast<ParticleIndex>(model.particleCount() - 1);
  const Vec3 r = sim.scene.initial.position[tool] - center;
  const Vec3 toolExpected = center + Vec3{-r.y, r.x, r.z + 0.05};  // r turned 90° about +z
  EXPECT_LT(norm(sim.world->state().position[tool] - toolExpected), 0.01)
      << "tool at " << sim.world->state().position[tool].x << ", "
      << sim.world->state().position[tool].y;
}

TEST(Control, TheCxxApiDrivesAJointBetweenSteps) {
  // robotics::Controller by hand: velocity mode, then a new target between steps.
  Sim sim(arm("{}", "[0, 0, 0]"));
  ASSERT_TRUE(sim.ok());
  robotics::Controller controller({}, sim.world->model());
  controller.setMode(0, robotics::JointMode::kVelocity);
  controller.setGains(0, 0.0, 0.0, 5.0);
  controller.setTarget(0, 0.5);
  controller.apply(*sim.world);
  for (int s = 0; s < 5000; ++s) {
    sim.world->step(2e-4);
    controller.step(*sim.world, sim.events);
  }
  EXPECT_NEAR(sim.rate(0), 0.5, 5e-3);
  controller.setTarget(0, -0.5);
  for (int s = 0; s < 5000; ++s) {
    sim.world->step(2e-4);
    controller.step(*sim.world, sim.events);
  }
  EXPECT_NEAR(sim.rate(0), -0.5, 5e-3);
  // Its state survives save and restore bit-exactly.
  const nlohmann::json saved = controller.save();
  robotics::Controller copy({}, sim.world->model());
  copy.restore(saved);
  EXPECT_EQ(copy.save().dump(), saved.dump());
}

TEST(Control, BrokenControlSectionsAreReportedWithPointerAndSuggestion) {
  const auto errors = [](const std::string& control) {
    SceneLoadResult r = loadSceneText(arm(control), "broken.json");
    std::string all;
    for (const auto& e : r.errors) all += e.format() + "\n";
    return all;
  };
  std::string e = errors(R"({"joints": {"arm.j9": {"mode": "position", "kp": 1, "target": 0}}})");
  EXPECT_NE(e.find("no joint named 'arm.j9'; did you mean 'arm.j1'?"), std::string::npos) << e;
  EXPECT_NE(e.find("/control/joints/arm.j9"), std::string::npos) << e;
  e = errors(R"({"joints": {"arm.j1": {"mode": "postion", "kp": 1, "target": 0}}})");
  EXPECT_NE(e.find("did you mean 'position'?"), std::string::npos) << e;
  e = errors(R"({"joints": {"arm.j1": {"mode": "position", "kp": 1, "target": 0, "kpp": 2}}})");
  EXPECT_NE(e.find("kpp"), std::string::npos) << e;
  e = errors(R"({"joints": {"arm.j1": {"mode": "position", "kp": 1,
                 "target": {"keyframes": [[0, 0], [0, 1]]}}}})");
  EXPECT_NE(e.find("/control/joints/arm.j1/target/keyframes/1/0"), std::string::npos) << e;
  e = errors(R"({"sequence": [{"name": "x", "at": 1, "after": 2}]})");
  EXPECT_NE(e.find("give one of"), std::string::npos) << e;
  e = errors(R"({"sequence": [{"when": {"contactForce": {"object": "ram", "above": 1}}}]})");
  EXPECT_NE(e.find("no object named 'ram'; did you mean 'arm'?"), std::string::npos) << e;
}

}  // namespace
}  // namespace robophi
