// Every connector: forces sum to zero, torques sum to zero, and the force is
// minus the gradient of its energy (central finite differences). MODEL §1.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "robophi/connector_forces.h"

namespace robophi {
namespace {

constexpr double kPi = std::numbers::pi;

Vec3 randomVec(std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

// Gradient of `energy` with respect to `point` by central differences.
template <typename EnergyFn>
Vec3 numericGradient(EnergyFn energy, Vec3& point, double h) {
  Vec3 g;
  double* coords[3] = {&point.x, &point.y, &point.z};
  double out[3];
  for (int k = 0; k < 3; ++k) {
    const double saved = *coords[k];
    *coords[k] = saved + h;
    const double plus = energy();
    *coords[k] = saved - h;
    const double minus = energy();
    *coords[k] = saved;
    out[k] = (plus - minus) / (2.0 * h);
  }
  g = {out[0], out[1], out[2]};
  return g;
}

void expectVecNear(const Vec3& a, const Vec3& b, double tol, const char* what) {
  EXPECT_NEAR(a.x, b.x, tol) << what;
  EXPECT_NEAR(a.y, b.y, tol) << what;
  EXPECT_NEAR(a.z, b.z, tol) << what;
}

// --- LS ---------------------------------------------------------------------

TEST(LinearSpringInvariants, ForcesAndTorquesSumToZero) {
  std::mt19937_64 rng(1);
  for (int trial = 0; trial < 200; ++trial) {
    const LinearSpring s{0, 1, 0.3, 1.0e3, 5.0};
    const Vec3 pA = randomVec(rng, 1.0), pB = randomVec(rng, 1.0);
    const Vec3 vA = randomVec(rng, 2.0), vB = randomVec(rng, 2.0);
    const LinearSpringForce f = linearSpringForce(s, pA, pB, vA, vB);
    const double scale = norm(f.onA) + 1.0;
    expectVecNear(f.onA + f.onB, {}, 1e-12 * scale, "force sum");
    expectVecNear(cross(pA, f.onA) + cross(pB, f.onB), {}, 1e-12 * scale, "torque sum");
    EXPECT_LE(f.dissipativePower, 0.0);
  }
}

TEST(LinearSpringInvariants, ForceIsMinusEnergyGradient) {
  std::mt19937_64 rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const LinearSpring s{0, 1, 0.4, 2.0e3, 0.0};
    Vec3 pA = randomVec(rng, 1.0), pB = randomVec(rng, 1.0);
    const LinearSpringForce f = linearSpringForce(s, pA, pB, {}, {});
    auto energy = [&] { return linearSpringForce(s, pA, pB, {}, {}).energy; };
    const double tol = 1e-6 * (norm(f.onA) + 1.0);
    expectVecNear(f.onA, -numericGradient(energy, pA, 1e-6), tol, "dE/dpA");
    expectVecNear(f.onB, -numericGradient(energy, pB, 1e-6), tol, "dE/dpB");
  }
}

// --- TS ---------------------------------------------------------------------

struct TorsionCase {
  Vec3 pA, pC, pB;
  TorsionSpring spring;
};

void checkTorsion(const TorsionCase& tc, const Vec3& vA, const Vec3& vC, const Vec3& vB,
                  double gradientTol) {
  Vec3 pA = tc.pA, pC = tc.pC, pB = tc.pB;
  const AngularSpringForce f = torsionSpringForce(tc.spring, pA, pC, pB, vA, vC, vB);
  const double scale = norm(f.onA) + norm(f.onB) + 1.0;
  expectVecNear(f.onA + f.onB + f.onC, {}, 1e-11 * scale, "TS force sum");
  expectVecNear(cross(pA, f.onA) + cross(pB, f.onB) + cross(pC, f.onC), {}, 1e-11 * scale,
                "TS torque sum");
  EXPECT_LE(f.dissipativePower, 1e-15);
  EXPECT_TRUE(isFinite(f.onA) && isFinite(f.onB) && isFinite(f.onC));
  if (gradientTol <= 0.0) return;
  TorsionSpring conservative = tc.spring;
  conservative.damping = 0.0;
  auto energy = [&] { return torsionSpringForce(conservative, pA, pC, pB, {}, {}, {}).energy; };
  const AngularSpringForce fc = torsionSpringForce(conservative, pA, pC, pB, {}, {}, {});
  expectVecNear(fc.onA, -numericGradient(energy, pA, 1e-7), gradientTol, "TS dE/dpA");
  expectVecNear(fc.onB, -numericGradient(energy, pB, 1e-7), gradientTol, "TS dE/dpB");
  expectVecNear(fc.onC, -numericGradient(energy, pC, 1e-7), gradientTol, "TS dE/dpC");
}

TEST(TorsionSpringInvariants, RandomConfigurations) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(0.1, kPi);
  for (int trial = 0; trial < 200; ++trial) {
    TorsionCase tc{randomVec(rng, 1.0), randomVec(rng, 1.0), randomVec(rng, 1.0),
                   TorsionSpring{0, 1, 2, angle(rng), 3.0, 0.2}};
    checkTorsion(tc, randomVec(rng, 1.0), randomVec(rng, 1.0), randomVec(rng, 1.0), 1e-5);
  }
}

// Arms of different lengths: the paper's force law would break angular
// momentum here; the gradient form must not.
TEST(TorsionSpringInvariants, UnequalArms) {
  TorsionCase tc{
      {2.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.1, 0.05}, TorsionSpring{0, 1, 2, 2.0, 10.0, 1.0}};
  checkTorsion(tc, {0.0, 1.0, 0.0}, {0.3, 0.0, 0.1}, {-1.0, 0.0, 0.0}, 1e-5);
}

// θ0 = 180°: a prismatic joint's TS. Finite and smooth at and near 180°.
TEST(TorsionSpringInvariants, NearStraight) {
  for (double offset : {1e-2, 1e-4, 1e-6, 1e-7, 0.0}) {
    // Rotate b off the line by `offset` rad about z, with a small tilt out of plane.
    const Vec3 pB{-std::cos(offset), std::sin(offset) * 0.8, std::sin(offset) * 0.6};
    TorsionCase tc{{1.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, pB, TorsionSpring{0, 1, 2, kPi, 5.0, 0.1}};
    checkTorsion(tc, {0.0, 0.2, 0.0}, {}, {0.0, -0.1, 0.3}, offset > 1e-6 ? 1e-5 : 0.0);
    const AngularSpringForce f = torsionSpringForce(tc.spring, tc.pA, tc.pC, tc.pB, {}, {}, {});
    // |F_b| = κ (π - θ) / |w| -> 0 linearly: a smooth restoring force.
    EXPECT_NEAR(norm(f.onB), 5.0 * offset, 1e-9) << "offset " << offset;
    EXPECT_NEAR(f.angle, kPi - offset, 1e-12);
  }
}

// --- JS ---------------------------------------------------------------------

void checkJoint(const Vec3& pA0, const Vec3& pC0, const Vec3& pB0, const Vec3& pD0,
                const JointSpring& spring, double gradientTol) {
  Vec3 pA = pA0, pC = pC0, pB = pB0, pD = pD0;
  const Vec3 vA{0.1, 0.2, -0.1}, vC{0.0, -0.1, 0.05}, vB{-0.3, 0.1, 0.0}, vD{0.05, 0.0, 0.1};
  const AngularSpringForce f = jointSpringForce(spring, pA, pC, pB, pD, vA, vC, vB, vD);
  const double scale = norm(f.onA) + norm(f.onB) + norm(f.onD) + 1.0;
  expectVecNear(f.onA + f.onB + f.onC + f.onD, {}, 1e-11 * scale, "JS force sum");
  expectVecNear(cross(pA, f.onA) + cross(pB, f.onB) + cross(pC, f.onC) + cross(pD, f.onD), {},
                1e-11 * scale, "JS torque sum");
  EXPECT_LE(f.dissipativePower, 1e-15);
  EXPECT_GE(f.angle, 0.0);
  EXPECT_LT(f.angle, 2.0 * kPi);
  JointSpring conservative = spring;
  conservative.damping = 0.0;
  auto energy = [&] {
    return jointSpringForce(conservative, pA, pC, pB, pD, {}, {}, {}, {}).energy;
  };
  const AngularSpringForce fc = jointSpringForce(conservative, pA, pC, pB, pD, {}, {}, {}, {});
  expectVecNear(fc.onA, -numericGradient(energy, pA, 1e-7), gradientTol, "JS dE/dpA");
  expectVecNear(fc.onB, -numericGradient(energy, pB, 1e-7), gradientTol, "JS dE/dpB");
  expectVecNear(fc.onC, -numericGradient(energy, pC, 1e-7), gradientTol, "JS dE/dpC");
  expectVecNear(fc.onD, -numericGradient(energy, pD, 1e-7), gradientTol, "JS dE/dpD");
}

TEST(JointSpringInvariants, RandomConfigurations) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi - 1e-9);
  for (int trial = 0; trial < 200; ++trial) {
    checkJoint(randomVec(rng, 1.0), randomVec(rng, 1.0), randomVec(rng, 1.0), randomVec(rng, 1.0),
               JointSpring{0, 1, 2, 3, angle(rng), 4.0, 0.3}, 1e-5);
  }
}

// A revolute joint as the builders make it: arms in the plane through c normal
// to the axis. Then no force acts on the reference particle (MODEL §1).
TEST(JointSpringInvariants, NoForceOnTheReferenceForInPlaneArms) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (int trial = 0; trial < 50; ++trial) {
    const double theta = angle(rng);
    const Vec3 pA{0.7, 0, 0}, pC{0, 0, 0}, pB{1.3 * std::cos(theta), 1.3 * std::sin(theta), 0};
    const AngularSpringForce f =
        jointSpringForce(JointSpring{0, 1, 2, 3, angle(rng), 4.0, 0.3}, pA, pC, pB, {0, 0, 0.2},
                         {0.1, 0.3, 0}, {}, {-0.2, 0.1, 0}, {});
    EXPECT_LT(norm(f.onD), 1e-12 * (norm(f.onA) + 1.0));
    EXPECT_NEAR(f.angle, theta, 1e-12);
  }
}

// Signed angle over [0, 2π): θ and 2π - θ are told apart by the reference.
TEST(JointSpringInvariants, SignedAngle) {
  const Vec3 pA{1, 0, 0}, pC{0, 0, 0}, pD{0, 0, 1};
  for (double theta : {0.3, 1.5, 3.0, 3.3, 4.7, 6.0}) {
    const Vec3 pB{std::cos(theta), std::sin(theta), 0.0};
    EXPECT_NEAR(jointAngle(pA, pC, pB, pD), theta, 1e-12);
    EXPECT_NEAR(jointAngle(pA, pC, pB, {0, 0, -1}), 2.0 * kPi - theta, 1e-12);
    // Arms lifted out of the plane: the angle about the axis is unchanged.
    EXPECT_NEAR(jointAngle(pA + Vec3{0, 0, 0.3}, pC, pB - Vec3{0, 0, 0.2}, pD), theta, 1e-12);
  }
}

// Across the 0/2π wrap the energy and force are continuous (Δθ is wrapped).
TEST(JointSpringInvariants, AcrossTheWrap) {
  const Vec3 pA{1, 0, 0}, pC{0, 0, 0}, pD{0, 0, 1};
  const JointSpring spring{0, 1, 2, 3, 0.1, 4.0, 0.0};
  double previousEnergy = -1.0;
  for (double theta : {-0.02, -0.01, -1e-6, 0.0, 1e-6, 0.01, 0.02}) {
    const Vec3 pB{std::cos(theta), std::sin(theta), 0.0};
    checkJoint(pA, pC, pB, pD, spring, 1e-5);
    const AngularSpringForce f = jointSpringForce(spring, pA, pC, pB, pD, {}, {}, {}, {});
    const double expected = 0.5 * 4.0 * (theta - 0.1) * (theta - 0.1);
    EXPECT_NEAR(f.energy, expected, 1e-12) << "theta " << theta;
    // Pulled toward θ0 = 0.1: b pushed the positive way round (+y near θ = 0).
    EXPECT_GT(f.onB.y, 0.0);
    if (previousEnergy >= 0.0) {
      EXPECT_LT(f.energy, previousEnergy);
    }
    previousEnergy = f.energy;
  }
}

// Through the straight position (θ = π) with the arms slightly out of the
// plane, the angle and the force stay continuous: no jump between θ and 2π - θ.
TEST(JointSpringInvariants, SmoothThroughStraight) {
  const Vec3 pA{1, 0, 0.01}, pC{0, 0, 0}, pD{0, 0, 1};
  const JointSpring spring{0, 1, 2, 3, 2.0, 4.0, 0.0};
  double previousAngle = -1.0;
  for (int k = -10; k <= 10; ++k) {
    const double theta = kPi + 1e-4 * k;
    const Vec3 pB{std::cos(theta), std::sin(theta), -0.02};
    const AngularSpringForce f = jointSpringForce(spring, pA, pC, pB, pD, {}, {}, {}, {});
    if (previousAngle >= 0.0) {
      EXPECT_NEAR(f.angle - previousAngle, 1e-4, 1e-9);
    }
    previousAngle = f.angle;
    checkJoint(pA, pC, pB, pD, spring, 1e-5);
  }
}


// An arm leaning onto the axis (a lattice crushed until the axis particle lines
// up with an arm): the angle's gradient grows as 1/|u⊥|, so the JS's energy is
// weighted by h (MODEL §1.3), 1 beyond 14.5° from the axis. The force stays
// F = −∇U (h's own gradient included), sums to zero, balances its torques, and
// stays bounded all the way onto the axis, where it vanishes; beyond the band
// it is the unweighted spring's, bit for bit.
TEST(JointSpringInvariants, BoundedAsAnArmLeansOntoTheAxis) {
  const Vec3 pC{0, 0, 0}, pD{0, 0, 0.006}, pB{0.02 * std::cos(2.5), 0.02 * std::sin(2.5), 0.001};
  const JointSpring spring{0, 1, 2, 3, kPi, 0.2, 0.01};
  const double length = 0.025;
  double largest = 0.0, edge = 0.0;
  for (double lean : {1.2, 0.6, 0.3, 0.26, 0.24, 0.2, 0.1, 0.05, 0.02, 0.01, 1e-3, 1e-5, 1e-8}) {
    // Arm a at `lean` rad from the axis, turned 1 rad from b about it.
    const Vec3 pA{length * std::sin(lean) * std::cos(1.0), length * std::sin(lean) * std::sin(1.0),
                  length * std::cos(lean)};
    const AngularSpringForce f = jointSpringForce(spring, pA, pC, pB, pD, {}, {}, {}, {});
    const double size = norm(f.onA) + norm(f.onB) + norm(f.onC) + norm(f.onD);
    largest = std::max(largest, size);
    if (lean == 0.26) edge = size;
    if (lean > 1e-4) checkJoint(pA, pC, pB, pD, spring, 1e-4 * (1.0 + size));
    const double error = f.angle - kPi;
    const double unweighted = 0.5 * 0.2 * error * error;
    if (std::sin(lean) >= 0.25) {
      EXPECT_EQ(f.energy, unweighted) << "lean " << lean;
    } else {
      EXPECT_LT(f.energy, unweighted) << "lean " << lean;
    }
    if (lean <= 1e-5) {
      EXPECT_LT(size, 1e-6) << "lean " << lean;
    }
  }
  // Bounded: inside the band the forces never pass 3× their size at its edge
  // (2.0× measured, at 11.5° from the axis); unweighted they grow as 1/sin.
  EXPECT_LT(largest, 3.0 * edge);
}

}  // namespace
}  // namespace robophi
