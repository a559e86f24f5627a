// Rigid bodies in reduced coordinates (include/robophi/multibody.h, docs/model.md §7),
// tested as physics: closed-form motion, conservation, hard stops, stable servos.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "robophi/multibody.h"

namespace robophi {
namespace {

const Vec3 kGravity{0, 0, -9.81};

// A chain of `links` revolute joints about y, each link a rod of length 1 m hanging down.
Multibody chain(int links, BodyJointKind base = BodyJointKind::kWeld) {
  Multibody mb;
  mb.name = "chain";
  if (base == BodyJointKind::kFree) {
    MultibodyBody b;
    b.name = "base";
    b.joint = BodyJointKind::kFree;
    b.mass = {2.0, {0.05, 0.0, 0.02}, Mat3::diagonal({0.1, 0.2, 0.25})};
    mb.bodies.push_back(b);
  }
  for (int i = 0; i < links; ++i) {
    MultibodyBody b;
    b.name = "link" + std::to_string(i);
    b.parent = static_cast<std::int32_t>(mb.bodies.size()) - 1;
    b.joint = BodyJointKind::kRevolute;
    b.X_PJ.translation = b.parent < 0 ? Vec3{0, 0, 3} : Vec3{0, 0, -1};
    b.axis = i % 2 == 0 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    b.mass = {1.0 + 0.3 * i, {0.02 * i, 0, -0.5}, Mat3::diagonal({0.09, 0.088, 0.004})};
    mb.bodies.push_back(b);
  }
  finalize(mb);
  return mb;
}

double totalEnergy(const Multibody& mb, const std::vector<double>& q, const std::vector<double>& v,
                   const Vec3& g, MultibodyKinematics& kin) {
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  return kineticEnergy(kin) + gravitationalEnergy(kin, g);
}

TEST(Multibody, APendulumSwingsAtItsClosedFormPeriod) {
  // A compound pendulum: ω² = m g d / I_pivot, at small amplitude.
  Multibody mb;
  MultibodyBody b;
  b.name = "bob";
  b.joint = BodyJointKind::kRevolute;
  b.axis = {0, 1, 0};
  b.mass = {2.0, {0, 0, -0.8}, Mat3::diagonal({0.05, 0.05, 0.01})};
  mb.bodies.push_back(b);
  finalize(mb);
  const double pivotInertia = 0.05 + 2.0 * 0.8 * 0.8;
  const double period = 2 * std::numbers::pi / std::sqrt(2.0 * 9.81 * 0.8 / pivotInertia);
  std::vector<double> q{1e-3}, v{0.0};
  MultibodyWorkspace ws;
  const double dt = 1e-4;
  double previous = q[0], t = 0.0, firstCrossing = -1.0, lastCrossing = -1.0;
  int crossings = 0;
  while (t < 10 * period) {
    stepMultibody(mb, q, v, {}, dt, kGravity, ws);
    t += dt;
    if (previous > 0 && q[0] <= 0) {  // downward zero crossing, interpolated
      const double at = t - dt * q[0] / (q[0] - previous);
      if (firstCrossing < 0) firstCrossing = at;
      lastCrossing = at;
      ++crossings;
    }
    previous = q[0];
  }
  ASSERT_GE(crossings, 9);
  EXPECT_NEAR((lastCrossing - firstCrossing) / (crossings - 1), period, 1e-4 * period);
}

TEST(Multibody, APassiveChainKeepsItsEnergy) {
  const Multibody mb = chain(5);
  std::vector<double> q{0.9, -0.4, 0.7, 0.2, -1.1}, v(5, 0.0);
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  const double e0 = totalEnergy(mb, q, v, kGravity, kin);
  double worst = 0.0;
  for (int s = 0; s < 20000; ++s) {  // 2 s at 0.1 ms
    stepMultibody(mb, q, v, {}, 1e-4, kGravity, ws);
    worst = std::max(worst, std::abs(totalEnergy(mb, q, v, kGravity, kin) - e0));
  }
  // Semi-implicit Euler: a bounded energy error of order dt, no drift.
  EXPECT_LT(worst, 2e-3 * 5 * 9.81 * 3);
}

// Joints with rotors (MJCF armature a): the rotors' ½ a q̇² is kinetic energy the
// step's matrix carries, and the scheme's ½ Δvᵀ(M + A)Δv its loss. With both booked,
// a chain with rotors keeps E + dissipated as well as the same chain without them
// (the step's own error); leaving the rotors' energy out misses what they hold.
struct RotorRun {
  double worst = 0.0, rotorsLargest = 0.0;
};
RotorRun swingWithRotors(double armature) {
  Multibody mb = chain(3);
  for (MultibodyBody& body : mb.bodies) body.armature = armature;
  std::vector<double> q{0.9, -0.4, 0.7}, v(3, 0.0);
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  RotorRun run;
  const auto rotors = [&] {
    double sum = 0.0;
    for (const MultibodyBody& body : mb.bodies) sum += 0.5 * body.armature * v[body.vStart] * v[body.vStart];
    return sum;
  };
  const double e0 = totalEnergy(mb, q, v, kGravity, kin);
  double dissipated = 0.0;
  for (int s = 0; s < 10000; ++s) {  // 1 s at 0.1 ms
    dissipated += stepMultibody(mb, q, v, {}, 1e-4, kGravity, ws).dissipated;
    const double r = rotors();
    run.worst = std::max(run.worst, std::abs(totalEnergy(mb, q, v, kGravity, kin) + r + dissipated - e0));
    run.rotorsLargest = std::max(run.rotorsLargest, r);
  }
  return run;
}

TEST(Multibody, RotorsKeepTheEnergyAccount) {
  const RotorRun bare = swingWithRotors(0.0), rotors = swingWithRotors(0.05);
  std::printf("account error over 1 s: %.3g J without rotors, %.3g J with (they hold up to %.3g J)\n",
              bare.worst, rotors.worst, rotors.rotorsLargest);
  EXPECT_GT(rotors.rotorsLargest, 0.1);
  EXPECT_LT(rotors.worst, 2.0 * bare.worst);
  EXPECT_LT(rotors.worst, 0.1 * rotors.rotorsLargest);
}

TEST(Multibody, InverseDynamicsIsTheMassMatrixTimesAccelerationPlusBias) {
  const Multibody mb = chain(4, BodyJointKind::kFree);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> q = neutralConfiguration(mb), v(mb.velocityCount), a(mb.velocityCount);
  for (int i = 7; i < mb.positionCount; ++i) q[i] = u(random);
  const Quaternion r = normalized({0.9, 0.2, -0.3, 0.1});
  q[3] = r.w, q[4] = r.x, q[5] = r.y, q[6] = r.z;
  for (double& x : v) x = u(random);
  for (double& x : a) x = u(random);
  MultibodyKinematics kin;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  const auto n = static_cast<std::size_t>(mb.velocityCount);
  std::vector<double> tau(n), bias(n), M(n * n);
  inverseDynamics(mb, kin, a.data(), kGravity, nullptr, tau.data());
  inverseDynamics(mb, kin, nullptr, kGravity, nullptr, bias.data());
  massMatrix(mb, kin, M.data());
  for (std::size_t i = 0; i < n; ++i) {
    double Ma = 0.0;
    for (std::size_t j = 0; j < n; ++j) Ma += M[i * n + j] * a[j];
    EXPECT_NEAR(tau[i], Ma + bias[i], 1e-10 * (1 + std::abs(tau[i]))) << "rate " << i;
    for (std::size_t j = 0; j < n; ++j) EXPECT_EQ(M[i * n + j], M[j * n + i]);
  }
  // ½ vᵀ M v is the kinetic energy.
  double vMv = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) vMv += v[i] * M[i * n + j] * v[j];
  EXPECT_NEAR(0.5 * vMv, kineticEnergy(kin), 1e-12 * vMv);
}

TEST(Multibody, AFreeFloatingTreeKeepsItsMomentumWithoutGravity) {
  const Multibody mb = chain(4, BodyJointKind::kFree);
  std::vector<double> q = neutralConfiguration(mb), v(mb.velocityCount, 0.0);
  q[7] = 0.4, q[8] = -0.3, q[9] = 1.0, q[10] = 0.2;
  v = {0.3, -1.2, 0.5, 0.1, 0.2, -0.3, 2.0, -1.0, 0.5, 3.0};
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  const SpatialVector h0 = spatialMomentum(kin);
  const Vec3 none{};
  for (int s = 0; s < 10000; ++s) stepMultibody(mb, q, v, {}, 1e-3, none, ws);  // 10 s
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  const SpatialVector h1 = spatialMomentum(kin);
  EXPECT_LT(norm(h1.angular - h0.angular), 1e-9 * norm(h0.angular));
  EXPECT_LT(norm(h1.linear - h0.linear), 1e-9 * norm(h0.linear));
  // The joints did move (the test is not of a frozen tree).
  EXPECT_GT(std::abs(q[10] - 0.2), 0.1);
}

TEST(Multibody, UnderGravityAFreeTreesMomentumChangesByItsWeightOnly) {
  const Multibody mb = chain(3, BodyJointKind::kFree);
  std::vector<double> q = neutralConfiguration(mb), v(mb.velocityCount, 0.0);
  v[0] = 1.0, v[7] = 2.0;
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  const SpatialVector h0 = spatialMomentum(kin);
  double mass = 0.0;
  for (double m : kin.mass) mass += m;
  for (int s = 0; s < 1000; ++s) stepMultibody(mb, q, v, {}, 1e-3, kGravity, ws);
  updateKinematics(mb, q.data(), kin);
  updateVelocities(mb, v.data(), kin);
  const SpatialVector h1 = spatialMomentum(kin);
  EXPECT_NEAR(h1.linear.z - h0.linear.z, -9.81 * mass * 1.0, 1e-9 * 9.81 * mass);
  EXPECT_NEAR(h1.linear.x, h0.linear.x, 1e-9);
}

TEST(Multibody, ALimitIsAHardStop) {
  Multibody mb = chain(3);
  for (MultibodyBody& b : mb.bodies) {
    b.lower = -0.3;
    b.upper = 0.25;
  }
  std::vector<double> q{0.0, 0.0, 0.0}, v{0.0, 0.0, 0.0};
  MultibodyInputs inputs;
  inputs.effort = {200.0, -150.0, 80.0};  // driven hard into the stops
  MultibodyWorkspace ws;
  double worst = 0.0;
  for (int s = 0; s < 3000; ++s) {
    stepMultibody(mb, q, v, inputs, 1e-3, kGravity, ws);
    for (int i = 0; i < 3; ++i) worst = std::max({worst, q[i] - 0.25, -0.3 - q[i]});
    if (s == 1500) inputs.effort = {-300.0, 300.0, -50.0};
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_NEAR(q[0], -0.3, 1e-9);
  EXPECT_NEAR(q[1], 0.25, 1e-9);
}

TEST(Multibody, StiffServosAtAMillisecondAreStable) {
  // Gains a MuJoCo user would use (kp 300, kd 20) on a light distal link at 1 kHz:
  // the servo is implicit, so the hold converges instead of ringing.
  Multibody mb = chain(3);
  mb.bodies[2].mass = {0.2, {0, 0, -0.05}, Mat3::diagonal({2e-4, 2e-4, 1e-5})};
  std::vector<double> q{0.0, 0.0, 0.0}, v{0.0, 0.0, 0.0};
  MultibodyInputs inputs;
  inputs.servoStiffness = {300, 300, 300};
  inputs.servoDamping = {20, 20, 20};
  inputs.servoTarget = {0.5, -0.4, 0.3};
  MultibodyWorkspace ws;
  MultibodyKinematics kin;
  for (int s = 0; s < 10000; ++s) {
    // Gravity compensation from the library's bias forces.
    updateKinematics(mb, q.data(), kin);
    std::vector<double> zero(3, 0.0), gravityForce(3);
    updateVelocities(mb, zero.data(), kin);
    inverseDynamics(mb, kin, nullptr, kGravity, nullptr, gravityForce.data());
    inputs.effort = gravityForce;
    stepMultibody(mb, q, v, inputs, 1e-3, kGravity, ws);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(q[i], inputs.servoTarget[i], 1e-4) << "joint " << i;
}

TEST(Multibody, FinalizeNamesWhatIsWrong) {
  Multibody mb = chain(2);
  mb.bodies[1].mass.mass = -1.0;
  try {
    finalize(mb);
    FAIL() << "accepted a negative mass";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("link1"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("mass"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace robophi
