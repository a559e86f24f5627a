// Integrators against closed-form motion (MODEL §2): oscillator, pendulum,
// free fall, energy drift, and the paper's scheme against symplectic Euler.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "robophi/world.h"

namespace robophi {
namespace {

constexpr double kPi = std::numbers::pi;

// A free particle of mass m on an LS of stiffness κ to a fixed anchor at the
// origin, displaced by `amplitude` along x from the rest length 1 m.
World makeOscillator(double stiffness, double mass, double amplitude, Integrator integrator,
                     double damping = 0.0) {
  Model model;
  model.gravity = {};
  const int object = model.addObject("oscillator", "particles");
  model.addParticle(1.0, 0.05, true, object);
  model.addParticle(mass, 0.05, false, object);
  model.linearSprings.push_back({0, 1, 1.0, stiffness, damping});
  State state = State::sizedFor(model);
  state.position[1] = {1.0 + amplitude, 0.0, 0.0};
  return World(std::move(model), std::move(state), integrator);
}

// Upward zero crossings of x(t) - rest, linearly interpolated.
struct Swing {
  std::vector<double> crossings;
  double maxDisplacement = 0.0;
};

Swing simulateSwing(World& world, double dt, int steps, double rest,
                    double (*coordinate)(const State&)) {
  Swing swing;
  double previous = coordinate(world.state()) - rest;
  for (int i = 0; i < steps; ++i) {
    EXPECT_EQ(world.step(dt), StepStatus::kOk);
    const double x = coordinate(world.state()) - rest;
    swing.maxDisplacement = std::max(swing.maxDisplacement, std::abs(x));
    if (previous < 0.0 && x >= 0.0) {
      swing.crossings.push_back(world.state().time - dt * x / (x - previous));
    }
    previous = x;
  }
  return swing;
}

double xOfParticle1(const State& s) { return s.position[1].x; }

class OscillatorTest : public ::testing::TestWithParam<Integrator> {};

// Period and amplitude within 0.1% over 10 periods at dt = T/200.
TEST_P(OscillatorTest, PeriodAndAmplitude) {
  const double stiffness = 100.0, mass = 1.0, amplitude = 0.1;
  const double period = 2.0 * kPi * std::sqrt(mass / stiffness);
  const double dt = period / 200.0;
  World world = makeOscillator(stiffness, mass, amplitude, GetParam());
  const Swing swing = simulateSwing(world, dt, 10 * 200 + 5, 1.0, xOfParticle1);
  ASSERT_GE(swing.crossings.size(), 10u);
  const double measured =
      (swing.crossings.back() - swing.crossings.front()) / double(swing.crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 1e-3);
  EXPECT_NEAR(swing.maxDisplacement / amplitude, 1.0, 1e-3);
}

// The undamped oscillator's energy error stays bounded: no secular growth
// over 1000 periods.
TEST_P(OscillatorTest, EnergyDriftBounded) {
  const double stiffness = 100.0, mass = 1.0;
  const double period = 2.0 * kPi * std::sqrt(mass / stiffness);
  const double dt = period / 200.0;
  World world = makeOscillator(stiffness, mass, 0.1, GetParam());
  const double e0 = 0.5 * stiffness * 0.01;
  double earlyMax = 0.0, lateMax = 0.0;
  const int steps = 1000 * 200;
  for (int i = 0; i < steps; ++i) {
    ASSERT_EQ(world.step(dt), StepStatus::kOk);
    const double error = std::abs(world.energy().mechanical() - e0) / e0;
    if (i < steps / 10) earlyMax = std::max(earlyMax, error);
    if (i >= steps - steps / 10) lateMax = std::max(lateMax, error);
  }
  // Symplectic Euler's energy oscillates by about ωδ/2 (1.6% here), Verlet's by (ωδ)²/8.
  EXPECT_LT(lateMax, 0.02);
  EXPECT_LT(lateMax, 1.5 * earlyMax + 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Symplectic, OscillatorTest,
                         ::testing::Values(Integrator::kSymplecticEuler,
                                           Integrator::kVelocityVerlet),
                         [](const auto& paramInfo) {
                           return std::string(integratorName(paramInfo.param));
                         });

// A damped oscillator dissipates exactly what its energy loses: the account
// E + dissipated stays constant to the integrator's accuracy.
TEST(EnergyAccount, DampedOscillatorBalances) {
  const double stiffness = 100.0, mass = 1.0, damping = 0.5;
  World world = makeOscillator(stiffness, mass, 0.1, Integrator::kVelocityVerlet, damping);
  const double dt = 1e-4;
  const double e0 = 0.5 * stiffness * 0.01;
  for (int i = 0; i < 50000; ++i) ASSERT_EQ(world.step(dt), StepStatus::kOk);
  const EnergyTally& e = world.energy();
  EXPECT_LT(e.mechanical(), 0.1 * e0);  // most of it is gone (ζ = 0.025, 5 s)
  EXPECT_NEAR(e.total(), e0, 1e-4 * e0);
  // Analytic decay of the envelope: E(t) ≈ E0 exp(-c t / m).
  EXPECT_NEAR(e.mechanical() / e0, std::exp(-damping * 5.0 / mass), 0.01);
}

// The paper's scheme (MODEL §2) gains energy on an undamped oscillator for any
// step: its step matrix has determinant 1 + (ωδ)²/2, so the energy grows as
// (1 + (ωδ)²/2)^n. Symplectic Euler (determinant 1) keeps it bounded. And symplectic
// Euler is stable just below ωδ = 2 and diverges just above.
TEST(PaperSchemeVersusSymplectic, StabilityDifference) {
  const double stiffness = 100.0, mass = 1.0;
  const double omega = std::sqrt(stiffness / mass);
  const double dt = 0.1 / omega;
  const int steps = static_cast<int>(10 * 2.0 * kPi / (omega * dt));  // 10 periods
  const double e0 = 0.5 * stiffness * 0.01;
  World taylor = makeOscillator(stiffness, mass, 0.1, Integrator::kTaylor);
  World symplectic = makeOscillator(stiffness, mass, 0.1, Integrator::kSymplecticEuler);
  for (int i = 0; i < steps; ++i) {
    taylor.step(dt);
    symplectic.step(dt);
  }
  const double taylorGain = taylor.energy().mechanical() / e0;
  const double symplecticGain = symplectic.energy().mechanical() / e0;
  const double predicted = std::pow(1.0 + std::pow(omega * dt, 2) / 2.0, steps);
  EXPECT_GT(taylorGain, 20.0);
  EXPECT_NEAR(taylorGain / predicted, 1.0, 0.05);
  EXPECT_NEAR(symplecticGain, 1.0, 0.06);

  for (double omegaDt : {1.9, 2.1}) {
    World w = makeOscillator(stiffness, mass, 0.1, Integrator::kSymplecticEuler);
    for (int i = 0; i < 200; ++i) w.step(omegaDt / omega);
    const double gain = w.energy().mechanical() / e0;
    if (omegaDt < 2.0) {
      EXPECT_LT(gain, 100.0) << "ωδ = " << omegaDt;
    } else {
      EXPECT_GT(gain, 1e10) << "ωδ = " << omegaDt;
    }
  }
}

// A pendulum of length L on a stiff LS under gravity: small-angle period
// 2π sqrt(L/g) (1 + θ0²/16) within 0.5%.
TEST(Pendulum, SmallAnglePeriod) {
  const double length = 1.0, g = 9.81, theta0 = 0.05;
  Model model;
  model.gravity = {0.0, 0.0, -g};
  const int object = model.addObject("pendulum", "particles");
  model.addParticle(1.0, 0.02, true, object);
  model.addParticle(1.0, 0.02, false, object);
  model.linearSprings.push_back({0, 1, length, 1.0e6, 0.0});
  State state = State::sizedFor(model);
  // Start at the static stretch so the radial mode is not excited.
  const double hang = length + g / 1.0e6;
  state.position[1] = {hang * std::sin(theta0), 0.0, -hang * std::cos(theta0)};
  World world(std::move(model), std::move(state), Integrator::kVelocityVerlet);
  const double expected = 2.0 * kPi * std::sqrt(hang / g) * (1.0 + theta0 * theta0 / 16.0);
  const Swing swing =
      simulateSwing(world, 1e-4, static_cast<int>(6.5 * expected / 1e-4), 0.0, xOfParticle1);
  ASSERT_GE(swing.crossings.size(), 5u);
  const double measured =
      (swing.crossings.back() - swing.crossings.front()) / double(swing.crossings.size() - 1);
  EXPECT_NEAR(measured / expected, 1.0, 0.005);
  EXPECT_NEAR(measured / expected, 1.0, 1e-4);  // in fact much better
}

// Free fall: the paper's scheme and velocity Verlet are exact for a constant
// force; symplectic Euler follows its own closed form p = p0 + v0 t - ½ g t (t + δ).
TEST(FreeFall, Exact) {
  const double g = 9.81, dt = 1e-3;
  const Vec3 v0{1.0, -0.5, 3.0};
  for (Integrator integrator :
       {Integrator::kTaylor, Integrator::kVelocityVerlet, Integrator::kSymplecticEuler}) {
    Model model;
    model.gravity = {0.0, 0.0, -g};
    model.addParticle(2.0, 0.1, false, model.addObject("ball", "particles"));
    State state = State::sizedFor(model);
    state.position[0] = {0.0, 0.0, 10.0};
    state.velocity[0] = v0;
    World world(std::move(model), std::move(state), integrator);
    for (int i = 0; i < 1000; ++i) world.step(dt);
    const double t = 1000 * dt;
    const double lag = integrator == Integrator::kSymplecticEuler ? dt : 0.0;
    const Vec3& p = world.state().position[0];
    const Vec3& v = world.state().velocity[0];
    EXPECT_NEAR(p.x, v0.x * t, 1e-12);
    EXPECT_NEAR(p.y, v0.y * t, 1e-12);
    EXPECT_NEAR(p.z, 10.0 + v0.z * t - 0.5 * g * t * (t + lag), 1e-11)
        << integratorName(integrator);
    EXPECT_NEAR(v.z, v0.z - g * t, 1e-11);
  }
}

}  // namespace
}  // namespace robophi
