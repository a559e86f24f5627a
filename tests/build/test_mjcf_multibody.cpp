// MJCF import (build/mjcf_multibody.h): an arm and a hand written for the tests
// (tests/build/mjcf/) load, their bodies' and sites' poses equal MuJoCo's own
// mj_kinematics at 20 random configurations within 1e-6 m, their masses, actuators
// and couplings come through, they hold under their position actuators, and what
// robophi cannot represent is refused naming the element and its line.
#include <gtest/gtest.h>

#ifdef ROBOPHI_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <utility>

#include "robophi/build/mjcf_multibody.h"
#include "robophi/kinematics.h"
#include "robophi/multibody.h"

namespace robophi {
namespace {

const std::string kMjcfDir = std::string(ROBOPHI_SOURCE_DIR) + "/tests/build/mjcf";

build::UrdfMultibody loadMjcf(const std::string& file, build::MjcfExtras* extras = nullptr) {
  build::MjcfMultibodySpec spec;
  spec.path = kMjcfDir + "/" + file;
  return build::makeMjcfMultibody(spec, extras);
}

TEST(MjcfMultibody, RecognisesMjcfPaths) {
  EXPECT_TRUE(build::isMjcfPath("robot.xml"));
  EXPECT_TRUE(build::isMjcfPath("a/b/robot.mjcf"));
  EXPECT_FALSE(build::isMjcfPath("robot.urdf"));
}

#ifndef ROBOPHI_HAVE_MUJOCO

TEST(MjcfMultibody, WithoutLibmujocoSaysWhatIsNeeded) {
  EXPECT_FALSE(build::mjcfAvailable());
  try {
    loadMjcf("arm.xml");
    FAIL() << "an MJCF file was read without libmujoco";
  } catch (const build::UrdfError& error) {
    EXPECT_NE(error.message().find("libmujoco-dev"), std::string::npos) << error.what();
  }
}

#else

std::string writeTemporary(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "robophi_mjcf_tests";
  std::filesystem::create_directories(dir);
  const auto path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

double angleBetween(const Mat3& a, const Mat3& b) { return norm(rotationVector(transpose(a) * b)); }

// Worst body and site position (m) and angle (rad) against mj_kinematics.
void compareWithMujoco(const std::string& file, double& worstPosition, double& worstAngle) {
  const build::UrdfMultibody robot = loadMjcf(file);
  const Multibody& mb = robot.multibody;
  char error[1000] = "";
  mjModel* m = mj_loadXML((kMjcfDir + "/" + file).c_str(), nullptr, error, sizeof error);
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  ASSERT_EQ(mb.positionCount, m->nq);
  std::mt19937 random(20);
  for (int c = 0; c < 20; ++c) {
    std::vector<double> q = neutralConfiguration(mb);
    for (const build::UrdfMultibodyJoint& j : robot.joints) {
      const int mjBall = mj_name2id(m, mjOBJ_JOINT, j.urdfName.c_str());
      if (j.type == "ball") {  // a random turn: the same unit quaternion (w, x, y, z) on both
        ASSERT_GE(mjBall, 0) << j.urdfName;
        double w[4], length = 0.0;
        for (double& x : w) {
          x = std::normal_distribution<double>(0.0, 1.0)(random);
          length += x * x;
        }
        for (int k = 0; k < 4; ++k) {
          q[static_cast<std::size_t>(j.positionIndex + k)] = w[k] / std::sqrt(length);
          d->qpos[m->jnt_qposadr[mjBall] + k] = w[k] / std::sqrt(length);
        }
        continue;
      }
      const MultibodyBody& body = mb.bodies[static_cast<std::size_t>(j.body)];
      const double lo = std::isfinite(body.lower) ? body.lower : -std::numbers::pi;
      const double hi = std::isfinite(body.upper) ? body.upper : std::numbers::pi;
      const double x = std::uniform_real_distribution<double>(lo, hi)(random);
      q[static_cast<std::size_t>(j.positionIndex)] = x;
      const int mjJoint = mj_name2id(m, mjOBJ_JOINT, j.urdfName.c_str());
      ASSERT_GE(mjJoint, 0) << j.urdfName;
      d->qpos[m->jnt_qposadr[mjJoint]] = x;
    }
    mj_kinematics(m, d);
    MultibodyKinematics kin;
    updateKinematics(mb, q.data(), kin);
    for (int b = 1; b < m->nbody; ++b) {
      const std::int32_t f = mb.frameIndex(mb.name + "." + mj_id2name(m, mjOBJ_BODY, b));
      ASSERT_GE(f, 0) << mj_id2name(m, mjOBJ_BODY, b);
      const Pose X = framePose(mb, kin, f);
      const mjtNum* p = d->xpos + 3 * b;
      const mjtNum* r = d->xquat + 4 * b;
      worstPosition = std::max(worstPosition, norm(X.translation - Vec3{p[0], p[1], p[2]}));
      worstAngle =
          std::max(worstAngle, angleBetween(X.rotation, rotationMatrix({r[0], r[1], r[2], r[3]})));
    }
    for (int s = 0; s < m->nsite; ++s) {
      const std::int32_t f = mb.frameIndex(mb.name + "." + mj_id2name(m, mjOBJ_SITE, s));
      ASSERT_GE(f, 0);
      const Pose X = framePose(mb, kin, f);
      const mjtNum* p = d->site_xpos + 3 * s;
      Mat3 R;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) R.m[i][k] = d->site_xmat[9 * s + 3 * i + k];
      worstPosition = std::max(worstPosition, norm(X.translation - Vec3{p[0], p[1], p[2]}));
      worstAngle = std::max(worstAngle, angleBetween(X.rotation, R));
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}

TEST(MjcfMultibody, TheArmAndTheHandMatchMujocosForwardKinematics) {
  for (const char* file : {"arm.xml", "hand.xml"}) {
    double position = 0.0, angle = 0.0;
    compareWithMujoco(file, position, angle);
    std::printf("%s: worst body/site position %.1e m, angle %.1e rad against mj_kinematics\n", file,
                position, angle);
    EXPECT_LT(position, 1e-6) << file;
    EXPECT_LT(angle, 1e-6) << file;
  }
}

// Ball joints (BodyJointKind::kBall): a chain of two, anchored off their bodies'
// origins in turned bodies, with a hinge between, matches mj_kinematics at 20
// random turns; passive and undamped it swings under gravity keeping its energy,
// and without gravity its angular momentum.
TEST(MjcfMultibody, BallJointsMatchMujocosForwardKinematicsAndSwingFreely) {
  double position = 0.0, angle = 0.0;
  compareWithMujoco("ball_chain.xml", position, angle);
  std::printf("ball_chain.xml: worst body/site position %.1e m, angle %.1e rad against mj_kinematics\n",
              position, angle);
  EXPECT_LT(position, 1e-6);
  EXPECT_LT(angle, 1e-6);
  const build::UrdfMultibody robot = loadMjcf("ball_chain.xml");
  const Multibody& mb = robot.multibody;
  ASSERT_EQ(mb.positionCount, 4 + 1 + 4);
  ASSERT_EQ(mb.velocityCount, 3 + 1 + 3);
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  const std::int32_t upper = mb.bodyIndex("ball_chain.upper");
  ASSERT_GE(upper, 0);
  for (const Vec3 gravity : {Vec3{0.0, 0.0, -9.81}, Vec3{}}) {
    std::vector<double> q = neutralConfiguration(mb), v(n, 0.0);
    v[0] = 1.5;  // the shoulder turning about its x and z axes, the wrist about y
    v[2] = -0.8;
    v[5] = 2.0;
    MultibodyInputs inputs;
    MultibodyWorkspace ws;
    MultibodyKinematics kin;
    const auto energyAndMomentum = [&](double& energy, Vec3& momentum) {
      updateKinematics(mb, q.data(), kin);
      updateVelocities(mb, v.data(), kin);
      energy = kineticEnergy(kin) + gravitationalEnergy(kin, gravity);
      // About the shoulder's centre A (the upper body's origin; the welded root
      // moves nothing): h_A = h_O − p_A × P.
      const SpatialVector h = spatialMomentum(kin);
      momentum = h.angular - cross(kin.X_WB[static_cast<std::size_t>(upper)].translation, h.linear);
    };
    double e0 = 0.0, e1 = 0.0;
    Vec3 h0, h1;
    energyAndMomentum(e0, h0);
    for (int s = 0; s < 4000; ++s) stepMultibody(mb, q, v, inputs, 2.5e-4, gravity, ws);
    energyAndMomentum(e1, h1);
    for (const std::size_t start : {std::size_t{0}, std::size_t{5}}) {  // unit quaternions
      double length = 0.0;
      for (std::size_t k = 0; k < 4; ++k) length += q[start + k] * q[start + k];
      EXPECT_NEAR(length, 1.0, 1e-12);
    }
    std::printf("ball chain, 1 s %s: energy %.6f -> %.6f J, angular momentum z %.6f -> %.6f\n",
                gravity.z != 0.0 ? "under gravity" : "without gravity", e0, e1, h0.z, h1.z);
    EXPECT_NEAR(e1, e0, 5e-3 * std::abs(e0) + 1e-3);
    // Gravity has no moment about the vertical through A; the ball joint passes no torque.
    EXPECT_NEAR(h1.z, h0.z, 1e-6 + 5e-3 * std::abs(h0.z));
    if (gravity.z == 0.0) {
      EXPECT_LT(norm(h1 - h0), 1e-3 * norm(h0));  // no gravity: all of h_A
    }
  }
}

TEST(MjcfMultibody, MassesJointsActuatorsAndCouplingsComeThrough) {
  build::MjcfExtras extras;
  const build::UrdfMultibody arm = loadMjcf("arm.xml", &extras);
  double mass = 0.0;
  for (const MultibodyBody& b : arm.multibody.bodies) mass += b.mass.mass;
  // 4 + 2.5 + 2 + 1.2 + 0.6 + 0.3 + 0.05, and j4's massless body between j4 and j5.
  EXPECT_NEAR(mass, 10.65, 1e-6);
  ASSERT_EQ(arm.joints.size(), 6u);
  EXPECT_EQ(arm.joints[5].type, "slide");
  const MultibodyBody& j2 = arm.multibody.bodies[static_cast<std::size_t>(arm.joints[1].body)];
  EXPECT_DOUBLE_EQ(j2.lower, -2.0);
  EXPECT_DOUBLE_EQ(j2.damping, 0.5);
  EXPECT_DOUBLE_EQ(j2.armature, 0.01);
  EXPECT_DOUBLE_EQ(j2.friction, 0.1);
  EXPECT_NEAR(extras.timestep, 0.001, 1e-15);
  ASSERT_EQ(extras.actuators.size(), 7u);
  EXPECT_EQ(extras.actuators[1].kind, build::MjcfActuator::Kind::kPosition);
  EXPECT_DOUBLE_EQ(extras.actuators[1].gain, 400.0);
  EXPECT_EQ(extras.actuators[5].kind, build::MjcfActuator::Kind::kVelocity);
  EXPECT_DOUBLE_EQ(extras.actuators[5].gain, 20.0);
  EXPECT_EQ(extras.actuators[6].kind, build::MjcfActuator::Kind::kMotor);
  EXPECT_DOUBLE_EQ(extras.actuators[6].gear, 50.0);
  EXPECT_DOUBLE_EQ(extras.actuators[6].ctrlUpper, 1.0);
  // Collision shapes: the visual sphere and the world's floor left out; the capsule
  // a cylinder; the mesh written as an OBJ file.
  ASSERT_EQ(arm.collisions.size(), 6u);
  EXPECT_EQ(arm.collisions[5].kind, build::UrdfCollisionShape::Kind::kMesh);
  EXPECT_TRUE(std::filesystem::exists(arm.collisions[5].mesh)) << arm.collisions[5].mesh;

  const build::UrdfMultibody hand = loadMjcf("hand.xml");
  EXPECT_EQ(hand.multibody.bodies[0].joint, BodyJointKind::kWeld);
  int coupled = 0;
  for (const build::UrdfMultibodyJoint& j : hand.joints)
    if (!j.mimicJoint.empty()) {
      ++coupled;
      EXPECT_DOUBLE_EQ(j.multiplier, 0.8);
    }
  EXPECT_EQ(coupled, 2);
}

// What holding a robot by its actuators came to.
struct Held {
  double worstError = 0.0, fastestRate = 0.0;
  // The worst |kp (q* − q) − g(q)| − friction loss over the joints of position
  // actuators (N·m or N): how far from the static balance of servo and gravity it ends.
  double imbalance = 0.0, largestGravity = 0.0;
};

// Holds a robot for `seconds` at every joint 0.3 (or nearer its range's middle) by
// servos of its position actuators' kp (× gear²) and velocity actuators' kv, with
// `compensate`: the gravity forces as efforts at every step (robophi run's hold).
Held holdByActuators(const std::string& file, double seconds, bool compensate) {
  build::MjcfExtras extras;
  const build::UrdfMultibody robot = loadMjcf(file, &extras);
  const Multibody& mb = robot.multibody;
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  std::vector<double> q = neutralConfiguration(mb), v(n, 0.0), atRest(n, 0.0), g(n, 0.0);
  for (const build::UrdfMultibodyJoint& j : robot.joints) {
    const MultibodyBody& body = mb.bodies[static_cast<std::size_t>(j.body)];
    const double margin =
        std::isfinite(body.upper - body.lower) ? 0.1 * (body.upper - body.lower) : 0;
    q[static_cast<std::size_t>(j.positionIndex)] =
        std::clamp(0.3, body.lower + margin, body.upper - margin);
  }
  const std::vector<double> target = q;
  MultibodyInputs inputs;
  inputs.servoStiffness.assign(n, 0.0);
  inputs.servoDamping.assign(n, 0.0);
  inputs.servoTarget = target;
  inputs.effort.assign(n, 0.0);
  for (const build::MjcfActuator& a : extras.actuators) {
    const auto i = static_cast<std::size_t>(a.velocityIndex);
    if (a.kind == build::MjcfActuator::Kind::kPosition)
      inputs.servoStiffness[i] = a.gain * a.gear * a.gear;
    if (a.kind == build::MjcfActuator::Kind::kVelocity)
      inputs.servoDamping[i] = a.gain * a.gear * a.gear;
  }
  // A coupled joint (a mimic) follows its own target by a servo of the fingers' kp.
  for (const build::UrdfMultibodyJoint& j : robot.joints)
    if (!j.mimicJoint.empty())
      inputs.servoStiffness[static_cast<std::size_t>(j.velocityIndex)] = 5.0;
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  const auto gravityAt = [&](const std::vector<double>& at, std::vector<double>& tau) {
    updateKinematics(mb, at.data(), kin);
    updateVelocities(mb, atRest.data(), kin);
    inverseDynamics(mb, kin, nullptr, extras.gravity, nullptr, tau.data());
  };
  for (int s = 0; s < static_cast<int>(seconds / extras.timestep); ++s) {
    if (compensate) gravityAt(q, inputs.effort);
    stepMultibody(mb, q, v, inputs, extras.timestep, extras.gravity, ws);
  }
  Held held;
  gravityAt(q, g);
  for (std::size_t i = 0; i < n; ++i) {
    held.worstError = std::max(held.worstError, std::abs(q[i] - target[i]));
    held.fastestRate = std::max(held.fastestRate, std::abs(v[i]));
    if (inputs.servoStiffness[i] == 0.0) continue;
    const double servo = inputs.servoStiffness[i] * (target[i] - q[i]) + inputs.effort[i];
    // Joint friction (a friction loss) may hold up to its bound of the difference.
    const double friction = mb.bodies[static_cast<std::size_t>(mb.dofBody[i])].friction;
    held.imbalance = std::max(held.imbalance, std::abs(servo - g[i]) - friction);
    held.largestGravity = std::max(held.largestGravity, std::abs(g[i]));
  }
  std::printf(
      "%s held %.0f s by its actuators%s: worst error %.2e, rate %.1e, servo − gravity %.1e "
      "(gravity up to %.2f)\n",
      file.c_str(), seconds, compensate ? " with gravity compensation" : "", held.worstError,
      held.fastestRate, held.imbalance, held.largestGravity);
  return held;
}

TEST(MjcfMultibody, TheArmAndTheHandHoldUnderTheirPositionActuators) {
  // Under gravity alone each ends where its servos balance gravity (MuJoCo's hold
  // without compensation), at rest; the arm with compensation stays where it is.
  for (const char* file : {"hand.xml", "arm.xml"}) {
    const Held held = holdByActuators(file, 20.0, false);
    EXPECT_LT(held.imbalance, 1e-4 * held.largestGravity) << file;
    EXPECT_LT(held.fastestRate, 1e-3) << file;
    EXPECT_LT(held.worstError, 0.1) << file;
  }
  const Held arm = holdByActuators("arm.xml", 2.0, true);
  EXPECT_LT(arm.worstError, 1e-9);
}

void expectRefused(const std::string& name, const std::string& text, const std::string& element,
                   int line) {
  const std::string path = writeTemporary(name, text);
  try {
    build::MjcfMultibodySpec spec;
    spec.path = path;
    build::makeMjcfMultibody(spec);
    FAIL() << name << " was accepted";
  } catch (const build::UrdfError& error) {
    EXPECT_NE(error.message().find(element), std::string::npos) << error.what();
    EXPECT_EQ(error.line(), line) << error.what();
  }
}

TEST(MjcfMultibody, WhatRobophiCannotRepresentIsRefusedNamingTheElement) {
  expectRefused("ball.xml", R"(<mujoco model="b">
  <worldbody>
    <body name="arm">
      <joint name="shoulder_ball" type="ball" limited="true" range="0 1"/>
      <geom type="sphere" size="0.1"/>
    </body>
  </worldbody>
</mujoco>)",
                "<joint> 'shoulder_ball': a ball joint with a range (a cone limit) of body 'arm'", 4);
  expectRefused("ellipsoid.xml", R"(<mujoco model="e">
  <worldbody>
    <body name="arm">
      <joint name="j" type="hinge"/>
      <geom name="egg" type="ellipsoid" size="0.1 0.2 0.3"/>
    </body>
  </worldbody>
</mujoco>)",
                "<geom> 'egg': an ellipsoid on body 'arm'", 5);
  expectRefused("weld.xml", R"(<mujoco model="w">
  <worldbody>
    <body name="a"><joint name="ja" type="hinge"/><geom type="sphere" size="0.1"/></body>
    <body name="b"><joint name="jb" type="hinge"/><geom type="sphere" size="0.1"/></body>
  </worldbody>
  <equality>
    <weld name="glue" body1="a" body2="b"/>
  </equality>
</mujoco>)",
                "<equality weld> 'glue'", 7);
  // MuJoCo's own compile errors come through with its message.
  expectRefused("broken.xml", "<mujoco><worldbody><body><joint type=\"hinge\"/></body>",
                "MuJoCo's compiler", 0);
}

#endif  // ROBOPHI_HAVE_MUJOCO

}  // namespace
}  // namespace robophi
