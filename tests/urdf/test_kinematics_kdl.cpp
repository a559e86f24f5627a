// The kinematics API (include/robophi/kinematics.h) on the iiwa, the Panda and the
// UR5 against orocos-kdl's chain solvers at 20 random configurations within the
// limits: the tip's pose (ChainFkSolverPos_recursive, 1e-9 m), its Jacobian
// (ChainJntToJacSolver, 1e-8), the gravity torques (ChainDynParam, 1e-6 N·m); the
// tip's spatial velocity equals J v; inverse kinematics reaches 100 random
// reachable poses per robot within 0.1 mm and 0.05° and lists those it misses.
#include <gtest/gtest.h>

#ifdef ROBOPHI_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#endif

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>

#include "robophi/build/urdf_multibody.h"
#include "robophi/kinematics.h"
#include "robophi/multibody.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)
const std::string kUr5 =
    kRobots + "/../robots-wild/example-robot-data/robots/ur_description/urdf/ur5_robot.urdf";

struct Arm {
  std::string path, root, tip;
};

std::vector<Arm> arms() {
  return {{kRobots + "/kuka_iiwa/model.urdf", "lbr_iiwa_link_0", "lbr_iiwa_link_7"},
          {kRobots + "/franka_panda/panda.urdf", "panda_link0", "panda_hand"},
          {kUr5, "base_link", "tool0"}};
}

bool armsPresent() {
  for (const Arm& arm : arms())
    if (!std::filesystem::exists(arm.path)) return false;
  return true;
}

build::UrdfMultibody load(const std::string& path) {
  build::UrdfMultibodySpec spec;
  spec.path = path;
  spec.packagePaths = {std::filesystem::path(path).parent_path().string(), kRobots,
                       kRobots + "/../robots-wild"};
  return build::makeUrdfMultibody(spec);
}

// A configuration uniform within the limits (±π where there are none).
std::vector<double> randomQ(const Multibody& mb, std::mt19937& random) {
  std::vector<double> q = neutralConfiguration(mb);
  for (const MultibodyJointInfo& j : movingJoints(mb)) {
    if (j.positionCount != 1) continue;
    const double lo = std::isfinite(j.lower) ? j.lower : -std::numbers::pi;
    const double hi = std::isfinite(j.upper) ? j.upper : std::numbers::pi;
    q[static_cast<std::size_t>(j.qStart)] = std::uniform_real_distribution<double>(lo, hi)(random);
  }
  return q;
}

TEST(Kinematics, JointsComeInRateOrderWithTheirLimits) {
  if (!armsPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  const build::UrdfMultibody robot = load(kRobots + "/kuka_iiwa/model.urdf");
  const std::vector<MultibodyJointInfo> joints = movingJoints(robot.multibody);
  ASSERT_EQ(joints.size(), 7u);
  for (std::size_t i = 0; i < joints.size(); ++i) {
    EXPECT_EQ(joints[i].vStart, static_cast<std::int32_t>(i));
    EXPECT_EQ(joints[i].name, robot.joints[i].name);
  }
  EXPECT_NEAR(joints[0].upper, 2.96705972839, 1e-9);
  EXPECT_NEAR(joints[0].effortLimit, 300.0, 1e-9);
}

TEST(Kinematics, TheFramesSpatialVelocityIsTheJacobianTimesV) {
  if (!armsPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  const build::UrdfMultibody robot = load(kRobots + "/franka_panda/panda.urdf");
  const Multibody& mb = robot.multibody;
  const std::int32_t tip = mb.frameIndex("panda.panda_hand");
  ASSERT_GE(tip, 0);
  std::mt19937 random(3);
  const auto nv = static_cast<std::size_t>(mb.velocityCount);
  const Vec3 p_FP{0.01, -0.02, 0.1};
  for (int c = 0; c < 5; ++c) {
    const std::vector<double> q = randomQ(mb, random);
    std::vector<double> v(nv);
    for (double& x : v) x = std::uniform_real_distribution<double>(-1, 1)(random);
    MultibodyKinematics kin;
    updateKinematics(mb, q.data(), kin);
    updateVelocities(mb, v.data(), kin);
    std::vector<double> J(6 * nv);
    calcFrameJacobian(mb, kin, tip, p_FP, J.data());
    const SpatialVector V = calcFrameSpatialVelocity(mb, kin, tip, p_FP);
    const double want[6] = {V.linear.x,  V.linear.y,  V.linear.z,
                            V.angular.x, V.angular.y, V.angular.z};
    for (std::size_t r = 0; r < 6; ++r) {
      double Jv = 0.0;
      for (std::size_t k = 0; k < nv; ++k) Jv += J[r * nv + k] * v[k];
      EXPECT_NEAR(Jv, want[r], 1e-12);
    }
    // And the point's velocity is the rate of its position (central differences).
    const double h = 1e-6;
    std::vector<double> qp = q, qm = q;
    integrateConfiguration(mb, qp.data(), v.data(), h);
    integrateConfiguration(mb, qm.data(), v.data(), -h);
    const Vec3 rate =
        (calcFramePose(mb, qp.data(), tip) * p_FP - calcFramePose(mb, qm.data(), tip) * p_FP) /
        (2 * h);
    EXPECT_LT(norm(rate - V.linear), 1e-7);
  }
}

#ifdef ROBOPHI_HAVE_KDL

struct Compared {
  double position = 0, jacobian = 0, gravity = 0;
};

Compared compareChain(const Arm& arm) {
  build::UrdfMultibody robot = load(arm.path);
  Multibody& mb = robot.multibody;
  KDL::Tree tree;
  EXPECT_TRUE(kdl_parser::treeFromFile(arm.path, tree)) << arm.path;
  KDL::Chain chain;
  EXPECT_TRUE(tree.getChain(arm.root, arm.tip, chain)) << arm.path;
  // What hangs off the chain (the Panda's fingers past its hand) is not in
  // KDL's chain: those bodies' mass is made negligible in robophi's copy for the
  // gravity comparison.
  Multibody chainOnly = mb;
  const std::int32_t tip = mb.frameIndex(mb.name + "." + arm.tip);
  EXPECT_GE(tip, 0) << arm.tip;
  const std::int32_t tipBody = mb.frames[static_cast<std::size_t>(tip)].body;
  for (std::size_t b = 0; b < mb.bodies.size(); ++b) {
    bool onChain = false;
    for (std::int32_t a = tipBody; a != -1; a = mb.bodies[static_cast<std::size_t>(a)].parent)
      onChain |= a == static_cast<std::int32_t>(b);
    if (!onChain) chainOnly.bodies[b].mass = {1e-30, {}, Mat3::diagonal({1e-30, 1e-30, 1e-30})};
  }
  const auto nv = static_cast<std::size_t>(mb.velocityCount);
  // Column of each chain joint in v.
  std::vector<std::size_t> column;
  for (const KDL::Segment& segment : chain.segments) {
    if (segment.getJoint().getType() == KDL::Joint::None) continue;
    for (const build::UrdfMultibodyJoint& j : robot.joints)
      if (j.urdfName == segment.getJoint().getName())
        column.push_back(static_cast<std::size_t>(j.velocityIndex));
  }
  EXPECT_EQ(column.size(), chain.getNrOfJoints());
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jacobian(chain);
  KDL::ChainDynParam dynamics(chain, KDL::Vector(0, 0, -9.81));
  std::mt19937 random(38);
  Compared worst;
  for (int c = 0; c < 20; ++c) {
    const std::vector<double> q = randomQ(mb, random);
    KDL::JntArray qKdl(chain.getNrOfJoints()), gKdl(chain.getNrOfJoints());
    for (unsigned i = 0; i < chain.getNrOfJoints(); ++i) qKdl(i) = q[column[i]];
    KDL::Frame X;
    EXPECT_GE(fk.JntToCart(qKdl, X), 0);
    const Pose X_WT = calcFramePose(mb, q.data(), tip);
    worst.position =
        std::max(worst.position, norm(X_WT.translation - Vec3{X.p.x(), X.p.y(), X.p.z()}));
    KDL::Jacobian JKdl(chain.getNrOfJoints());
    EXPECT_GE(jacobian.JntToJac(qKdl, JKdl), 0);
    MultibodyKinematics kin;
    updateKinematics(mb, q.data(), kin);
    std::vector<double> J(6 * nv);
    calcFrameJacobian(mb, kin, tip, {}, J.data());
    for (unsigned i = 0; i < chain.getNrOfJoints(); ++i)
      for (unsigned r = 0; r < 6; ++r)
        worst.jacobian = std::max(worst.jacobian, std::abs(J[r * nv + column[i]] - JKdl(r, i)));
    EXPECT_GE(dynamics.JntToGravity(qKdl, gKdl), 0);
    // KDL's JntToGravity is the torque gravity exerts; robophi's the torque that holds.
    updateKinematics(chainOnly, q.data(), kin);
    const std::vector<double> atRest(nv, 0.0);
    updateVelocities(chainOnly, atRest.data(), kin);
    std::vector<double> tau(nv);
    inverseDynamics(chainOnly, kin, nullptr, {0, 0, -9.81}, nullptr, tau.data());
    for (unsigned i = 0; i < chain.getNrOfJoints(); ++i)
      worst.gravity = std::max(worst.gravity, std::abs(tau[column[i]] - gKdl(i)));
  }
  return worst;
}

TEST(Kinematics, TipPoseJacobianAndGravityEqualKdlsChainSolvers) {
  if (!armsPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const Arm& arm : arms()) {
    const Compared worst = compareChain(arm);
    std::printf("%s → %s: worst tip position %.1e m, Jacobian %.1e, gravity torque %.1e N·m\n",
                arm.path.c_str(), arm.tip.c_str(), worst.position, worst.jacobian, worst.gravity);
    EXPECT_LT(worst.position, 1e-9) << arm.path;
    EXPECT_LT(worst.jacobian, 1e-8) << arm.path;
    EXPECT_LT(worst.gravity, 1e-6) << arm.path;
  }
}

#endif  // ROBOPHI_HAVE_KDL

TEST(Kinematics, InverseKinematicsReachesRandomReachablePoses) {
  if (!armsPresent()) GTEST_SKIP() << "no robots at " << kRobots << " (ROBOPHI_ROBOTS_DIR)";
  for (const Arm& arm : arms()) {
    const build::UrdfMultibody robot = load(arm.path);
    const Multibody& mb = robot.multibody;
    const std::int32_t tip = mb.frameIndex(mb.name + "." + arm.tip);
    ASSERT_GE(tip, 0);
    std::mt19937 random(100);
    int reached = 0, attempts = 0;
    double worstPosition = 0, worstAngle = 0;
    for (int t = 0; t < 100; ++t) {
      const std::vector<double> qTarget = randomQ(mb, random);
      const Pose target = calcFramePose(mb, qTarget.data(), tip);
      // Every other target from the neutral configuration, the rest from another random one.
      const std::vector<double> q0 = t % 2 == 0 ? neutralConfiguration(mb) : randomQ(mb, random);
      const InverseKinematicsResult ik = solveInverseKinematics(mb, tip, target, q0);
      attempts += ik.attempts;
      const Pose got = calcFramePose(mb, ik.q.data(), tip);
      const double dp = norm(got.translation - target.translation);
      const double angle = norm(rotationVector(transpose(got.rotation) * target.rotation));
      for (const MultibodyJointInfo& j : movingJoints(mb)) {
        EXPECT_GE(ik.q[static_cast<std::size_t>(j.qStart)], j.lower);
        EXPECT_LE(ik.q[static_cast<std::size_t>(j.qStart)], j.upper);
      }
      if (dp <= 1e-4 && angle <= 0.05 * std::numbers::pi / 180) {
        ++reached;
        EXPECT_TRUE(ik.success);
        worstPosition = std::max(worstPosition, dp);
        worstAngle = std::max(worstAngle, angle);
      } else {
        std::printf("  %s: target %d not reached: %.2e m, %.2e rad after %d attempts\n",
                    arm.tip.c_str(), t, dp, angle, ik.attempts);
      }
    }
    std::printf("%s: IK reached %d of 100 poses (%d attempts in all; worst %.1e m, %.1e rad)\n",
                arm.path.c_str(), reached, attempts, worstPosition, worstAngle);
    EXPECT_GE(reached, 95) << arm.path;
  }
}

}  // namespace
}  // namespace robophi
