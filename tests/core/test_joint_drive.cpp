// Joint motors and losses in the core (MODEL §1.6): the effort acts through the
// joint's own particles (forces sum to zero, torques balance, power = τ q̇), a
// free rotor under constant torque accelerates at τ/I, and the energy account
// stays closed while a motor spins it against damping.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "robophi/adaptive_step.h"
#include "robophi/connector_forces.h"
#include "robophi/evaluation.h"
#include "robophi/joints.h"
#include "robophi/world.h"

namespace robophi {
namespace {

// A rotor: a fixed axle (centre c at the origin, axis particle d on +z) and a
// fixed parent arm a on +x; a ring of `kRing` particles of mass kDriveMass at radius
// kR about the axle, every pair tied by a stiff LS and each tied to c and d.
// Joint "rotor" is the JS (a, c, ring[0], d). I = kRing kDriveMass kR².
constexpr int kRing = 6;
constexpr double kDriveMass = 0.1, kR = 0.2;
constexpr double kInertia = kRing * kDriveMass * kR * kR;  // 0.024 kg·m²

struct Rotor {
  Model model;
  State state;
  Rotor() {
    const std::int32_t object = model.addObject("rotor", "particles");
    const auto add = [&](const Vec3& p, bool fixed) {
      state.position.push_back(p);
      state.velocity.push_back({});
      return model.addParticle(kDriveMass, 0.01, fixed, object);
    };
    const ParticleIndex c = add({0, 0, 0}, true), d = add({0, 0, 0.1}, true);
    const ParticleIndex a = add({0.3, 0, 0}, true);
    std::vector<ParticleIndex> ring;
    for (int k = 0; k < kRing; ++k) {
      const double phi = 2.0 * M_PI * (k + 0.5) / kRing;
      ring.push_back(add({kR * std::cos(phi), kR * std::sin(phi), 0.0}, false));
    }
    const auto link = [&](ParticleIndex i, ParticleIndex j) {
      model.linearSprings.push_back(
          {i, j, norm(state.position[i] - state.position[j]), 1.0e5, 1.0});
    };
    for (int i = 0; i < kRing; ++i) {
      link(ring[i], c);
      link(ring[i], d);
      for (int j = i + 1; j < kRing; ++j) link(ring[i], ring[j]);
    }
    const double angle = jointAngle(state.position[a], state.position[c], state.position[ring[0]],
                                    state.position[d]);
    model.jointSprings.push_back({a, c, ring[0], d, angle, 0.0, 0.0});
    model.joints.push_back({"rotor", JointKind::kRevolute, 0, -1, angle});
    model.gravity = {};
    model.contact.enabled = false;
  }
};

Vec3 netForce(const std::vector<Vec3>& f) {
  Vec3 sum{};
  for (const Vec3& x : f) sum += x;
  return sum;
}

Vec3 netTorque(const std::vector<Vec3>& p, const std::vector<Vec3>& f) {
  Vec3 sum{};
  for (std::size_t i = 0; i < p.size(); ++i) sum += cross(p[i], f[i]);
  return sum;
}

TEST(JointDrive, EffortSumsToZeroBalancesTorquesAndItsPowerIsTauQdot) {
  // Random positions and velocities of a, c, b, d (a JS) and of origin, slider,
  // end (a prismatic joint's TS), off the plane and off the line.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto rv = [&] { return Vec3{u(rng), u(rng), u(rng)}; };
  for (int trial = 0; trial < 20; ++trial) {
    const Vec3 pA = rv(), pC = rv(), pB = rv(), pD = rv();
    const Vec3 vA = rv(), vC = rv(), vB = rv(), vD = rv();
    const CoordinateGradient g = jointAngleGradient(pA, pC, pB, pD);
    ASSERT_TRUE(g.valid);
    const double tau = 2.5;
    const Vec3 sum = (g.a + g.b + g.c + g.d) * tau;
    const Vec3 torque = (cross(pA, g.a) + cross(pB, g.b) + cross(pC, g.c) + cross(pD, g.d)) * tau;
    EXPECT_LT(norm(sum), 1e-12);
    EXPECT_LT(norm(torque), 1e-12);
    EXPECT_NEAR(g.rate(vA, vC, vB, vD), jointAngleRate(pA, pC, pB, pD, vA, vC, vB, vD), 1e-12);
    // Prismatic: sums, torques, and ∂q/∂p by finite differences.
    const CoordinateGradient s = prismaticGradient(pA, pC, pB);
    EXPECT_LT(norm(s.a + s.b + s.c), 1e-12);
    EXPECT_LT(norm(cross(pA, s.a) + cross(pC, s.c) + cross(pB, s.b)), 1e-12);
    const double h = 1e-7;
    const Vec3 ex{1, 0, 0};
    EXPECT_NEAR((prismaticGradient(pA, pC, pB + ex * h).value - s.value) / h, s.b.x, 1e-5);
    EXPECT_NEAR((prismaticGradient(pA + ex * h, pC, pB).value - s.value) / h, s.a.x, 1e-5);
  }
  // Through evaluate(): the rotor's forces with only a motor effort (no gravity,
  // springs at rest): net force and torque 0, Σ F·v = τ q̇ = the driving power
  // (the fixed particles' share cancels against their own term).
  Rotor rotor;
  rotor.model.joints[0].drive.effort = 0.1;
  for (std::size_t i = 3; i < rotor.state.velocity.size(); ++i)
    rotor.state.velocity[i] = cross(Vec3{0, 0, 1.5}, rotor.state.position[i]);
  CompiledModel compiled(rotor.model);
  Workspace workspace;
  const Evaluation& e = evaluate(compiled, rotor.state, workspace);
  EXPECT_LT(norm(netForce(e.force)), 1e-12);
  EXPECT_LT(norm(netTorque(rotor.state.position, e.force)), 1e-12);
  EXPECT_DOUBLE_EQ(e.jointMotorEffort.at(0), 0.1);
  EXPECT_NEAR(e.drivingPower, 0.1 * 1.5, 1e-12);
  double power = 0.0;
  for (std::size_t i = 0; i < e.force.size(); ++i)
    power += dot(e.force[i], rotor.state.velocity[i]);
  EXPECT_NEAR(power, 0.15, 1e-12);
}

TEST(JointDrive, AFreeRotorUnderConstantTorqueAcceleratesAtTauOverI) {
  Rotor rotor;
  World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  const double tau = 0.1;  // N·m: α = τ/I = 4.167 rad/s²
  world.setJointEffort(0, tau);
  const double dt = 1e-4;
  for (int s = 0; s < 10000; ++s) world.step(dt);
  const double t = world.state().time;
  const double alpha = jointRate(world.model(), world.state(), 0) / t;
  EXPECT_NEAR(alpha, tau / kInertia, 0.01 * tau / kInertia) << "α = " << alpha;
  EXPECT_NEAR(jointPosition(world.model(), world.state(), 0),
              wrapSigned(0.5 * tau / kInertia * t * t), 0.01 * 0.5 * tau / kInertia * t * t);
  // The motor's work is the rotor's kinetic energy (no damping, springs near rest).
  const EnergyTally e = world.energy();
  EXPECT_NEAR(e.external, e.kinetic, 1e-3 * e.kinetic);
}

TEST(JointDrive, TheEnergyAccountStaysClosedWhileAMotorSpinsAgainstDamping) {
  Rotor rotor;
  JointDrive drive;
  drive.effort = 0.1;    // N·m
  drive.damping = 0.05;  // N·m·s/rad: steady rate τ/b = 2 rad/s, time constant I/b = 0.48 s
  rotor.model.joints[0].drive = drive;
  for (Integrator integrator : {Integrator::kVelocityVerlet, Integrator::kSymplecticEuler}) {
    World world(rotor.model, rotor.state, integrator);
    const double total0 = world.energy().total();
    for (int s = 0; s < 30000; ++s) world.step(1e-4);
    const EnergyTally e = world.energy();
    // The motor put in ≈ 0.1 × 2 × 2.5 = 0.5 J, nearly all dissipated.
    EXPECT_GT(e.external, 0.4);
    EXPECT_NEAR(e.total(), total0, 1e-4 * e.external) << integratorName(integrator);
    EXPECT_NEAR(jointRate(world.model(), world.state(), 0), 2.0, 0.01 * 2.0);
    EXPECT_NEAR(world.evaluation().jointLossEffort.at(0), -0.1, 1e-3);
  }
}

TEST(JointDrive, EffortAndVelocityLimitsBoundTheMotor) {
  Rotor rotor;
  JointDrive drive;
  drive.rateGain = 10.0;  // N·m·s/rad towards 20 rad/s: 200 N·m, clamped to 0.05
  drive.targetRate = 20.0;
  drive.effortLimit = 0.05;
  drive.velocityLimit = 1.0;  // rad/s
  rotor.model.joints[0].drive = drive;
  World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  double fastest = 0.0;
  for (int s = 0; s < 20000; ++s) {
    world.step(1e-4);
    if (s == 1999) {  // t = 0.2 s: α = 0.05 / I
      EXPECT_NEAR(jointRate(world.model(), world.state(), 0), 0.05 / kInertia * 0.2, 1e-3);
      EXPECT_DOUBLE_EQ(world.evaluation().jointMotorEffort[0], 0.05);
    }
    fastest = std::max(fastest, jointRate(world.model(), world.state(), 0));
  }
  // Held at the velocity limit: the motor stops pushing there (the rate read at
  // b carries the ring's own vibration, a few mrad/s).
  EXPECT_LT(fastest, 1.01);
  EXPECT_GT(jointRate(world.model(), world.state(), 0), 0.99);
}

TEST(JointDrive, CoulombFrictionHoldsAJointAgainstASmallerEffort) {
  Rotor rotor;
  JointDrive drive;
  drive.effort = 0.05;   // N·m, below
  drive.friction = 0.1;  // N·m
  drive.frictionVelocity = 0.01;
  rotor.model.joints[0].drive = drive;
  World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  for (int s = 0; s < 10000; ++s) world.step(1e-4);
  // It creeps at the rate where friction balances the effort: v_f τ / F_c.
  EXPECT_NEAR(jointRate(world.model(), world.state(), 0), 0.005, 2e-4);
  // Edits: a bad drive is refused with its field named; the same effort is no edit.
  EXPECT_THROW(world.setJointEffort(1, 0.0), std::out_of_range);
  EXPECT_THROW(world.setJointEffort(0, std::nan("")), std::invalid_argument);
  JointDrive bad;
  bad.effortLimit = 0.0;
  try {
    world.setJointDrive(0, bad);
    ADD_FAILURE() << "a zero effort limit was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("effortLimit"), std::string::npos) << e.what();
  }
  world.setJointEffort(0, 0.05);
  EXPECT_EQ(world.bookExternalWork(), 0.0);
}


// A rate drive is a damper on its joint (MODEL §1.6): the evaluation bounds its
// rate, M⁻¹ g Ḡ Ḡᵀ, exactly for one drive (g |∂θ/∂p_b|² / m_b = g / (m R²) through
// ring[0] alone; g / I through the whole ring as motor particles), and for two
// drives on the same particles their sum.
TEST(JointDrive, TheDampingRateOfADriveIsBoundedExactly) {
  const double g = 3.0;  // N·m·s/rad
  Rotor rotor;
  rotor.model.joints[0].drive.rateGain = g;
  {
    World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
    EXPECT_NEAR(world.evaluation().driveDampingRate, g / (kDriveMass * kR * kR),
                1e-9 * g / kDriveMass);
  }
  rotor.model.joints[0].drive.damping = 1.0;  // adds to the gain
  rotor.model.joints.push_back(rotor.model.joints[0]);
  rotor.model.joints.back().name = "twin";
  {
    World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
    EXPECT_NEAR(world.evaluation().driveDampingRate, 2.0 * (g + 1.0) / (kDriveMass * kR * kR),
                1e-9 * g / kDriveMass);
  }
  rotor.model.joints.pop_back();
  rotor.model.joints[0].drive.damping = 0.0;
  for (ParticleIndex p = 4; p < 3 + kRing; ++p) rotor.model.joints[0].motorParticles.push_back(p);
  World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  EXPECT_NEAR(world.evaluation().driveDampingRate, g / kInertia, 1e-9 * g / kInertia);
  // No drive, or one of effort alone: no damping.
  rotor.model.joints[0].drive = JointDrive{};
  rotor.model.joints[0].drive.effort = 0.1;
  World plain(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  EXPECT_EQ(plain.evaluation().driveDampingRate, 0.0);
}

// The adaptive step keeps below a stiff rate drive's damping limit (MODEL §4:
// the drive's rate on top of the connectors'): the rotor spun up to 5 rad/s by a
// gain of 40 N·m·s/rad through ring[0] (a rate of 1e4 /s) keeps its energy
// account, where a constant step at 3 / rate loses it.
TEST(JointDrive, TheAdaptiveStepKeepsBelowAStiffRateDrive) {
  Rotor rotor;
  rotor.model.joints[0].drive.rateGain = 40.0;
  rotor.model.joints[0].drive.targetRate = 5.0;
  const double rate = 40.0 / (kDriveMass * kR * kR);
  World world(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  AdaptiveStepper stepper(world.model(), AdaptiveStepSettings{});
  double largest = 0.0;
  while (world.state().time < 0.5) {
    const AdaptiveStepResult r = stepper.advance(world, 0.5 - world.state().time);
    ASSERT_TRUE(r.ok) << r.failure;
    largest = std::max(largest, r.dt);
  }
  EXPECT_LT(largest, 2.0 / rate);
  const EnergyTally e = world.energy();
  EXPECT_NEAR(e.total(), 0.0, 1e-3 * e.external);
  EXPECT_NEAR(jointRate(world.model(), world.state(), 0), 5.0, 0.05);
  World constant(rotor.model, rotor.state, Integrator::kVelocityVerlet);
  const double dt = 3.0 / rate;
  for (int s = 0; s < static_cast<int>(0.5 / dt); ++s) constant.step(dt);
  const EnergyTally c = constant.energy();
  EXPECT_GT(std::abs(c.total()), 0.05 * std::abs(c.external))
      << "the drive's limit should show at a constant step of 3 / rate";
}

}  // namespace
}  // namespace robophi
