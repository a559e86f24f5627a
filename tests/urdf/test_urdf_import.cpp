// The URDF importer on every robot of ../shared/robots: it imports, `robophi info`'s
// figures per link (mass within 1%, centre of mass within 2 mm, principal moments
// within 10% of the URDF's), joints and frames as the file says, and a 2 s run on
// the ground without divergence; zero mass on a moving link is refused.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "robophi/build/urdf.h"
#include "robophi/joints.h"
#include "robophi/scene/scene.h"
#include "run/object_report.h"
#include "run/runner.h"
#include "test_files.h"

namespace robophi {
namespace {

using testing::kRobots;  // ROBOPHI_ROBOTS_DIR (test_files.h)
const std::string kBroken = std::string(ROBOPHI_SOURCE_DIR) + "/tests/urdf/broken/";

struct RobotCase {
  const char* file;
  int links, movingJoints;
};

const RobotCase kCases[] = {
    {"kuka_iiwa/model.urdf", 8, 7},
    {"kuka_iiwa/model_for_sdf.urdf", 8, 7},
    {"kuka_iiwa/model_free_base.urdf", 8, 7},
    {"kuka_iiwa/model_vr_limits.urdf", 8, 7},
    {"franka_panda/panda.urdf", 13, 9},
    {"husky/husky.urdf", 11, 4},
    {"r2d2/r2d2.urdf", 16, 8},
    {"pr2_gripper/pr2_gripper.urdf", 5, 2},
    {"cartpole/cartpole.urdf", 3, 2},
};

Scene loadRobot(const std::string& file) {
  UrdfSceneOptions options;
  options.packagePaths = {kRobots + "/franka_panda"};
  options.rigid = false;  // the paper's model: links filled with particles
  SceneLoadResult result = loadUrdfFile(kRobots + "/" + file, options);
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) return Scene{};
  return std::move(*result.scene);
}

class UrdfRobots : public ::testing::TestWithParam<RobotCase> {};

TEST_P(UrdfRobots, InfoMatchesTheUrdfPerLink) {
  const RobotCase& c = GetParam();
  const Scene scene = loadRobot(c.file);
  ASSERT_EQ(scene.urdfRobots.size(), 1u);
  const build::UrdfRobot& robot = *scene.urdfRobots[0];
  EXPECT_EQ(static_cast<int>(robot.links.size()), c.links);
  EXPECT_EQ(static_cast<int>(scene.model.joints.size()), c.movingJoints);
  const SceneReport report = reportScene(scene);
  int compared = 0;
  for (const ObjectReport& r : report.objects) {
    SCOPED_TRACE(r.name);
    EXPECT_EQ(r.kind, "link");  // carriers are reported with their link
    ASSERT_TRUE(r.urdfLink);
    if (r.notional) continue;
    ++compared;
    EXPECT_LT(r.massError, 0.01);
    EXPECT_LT(r.centerOfMassError, 2e-3);
    for (int k = 0; k < 3; ++k) EXPECT_LT(r.momentError[k], 0.10) << "moment " << k;
  }
  EXPECT_GT(compared, 0);
  // Every moving joint is a model joint at q = 0 as built.
  for (const build::UrdfJoint& j : robot.joints) {
    if (j.type == build::UrdfJointType::kFixed) continue;
    const auto index = findJoint(scene.model, j.modelJoint);
    ASSERT_TRUE(index.has_value()) << j.modelJoint;
    EXPECT_NEAR(jointPosition(scene.model, scene.initial, *index), 0.0, 1e-9) << j.name;
  }
  // On the ground: the lowest particle, or a round wheel's cylinder (docs/contact.md
  // "Round wheels"), rests on z = 0.
  double lowest = 1e9;
  for (ParticleIndex i = 0; i < scene.model.particleCount(); ++i)
    if (scene.model.objects[static_cast<std::size_t>(scene.model.objectOf[i])].kind == "link")
      lowest = std::min(
          lowest, scene.initial.position[static_cast<std::size_t>(i)].z - scene.model.radius[i]);
  for (const RimRing& rim : scene.model.rims) {
    if (!rim.isCylinder()) continue;
    const Vec3 hub = scene.initial.position[static_cast<std::size_t>(rim.hub)];
    const Vec3 n = scene.initial.position[static_cast<std::size_t>(rim.axisParticle)] - hub;
    const double nz = n.z / norm(n);
    lowest = std::min(lowest, hub.z + nz * rim.axialOffset -
                                  rim.sphereRadius * std::sqrt(1.0 - nz * nz) -
                                  rim.halfLength * std::abs(nz));
  }
  EXPECT_NEAR(lowest, 0.0, 1e-12);
}

// Slow/* (label slow): 2 s of each robot.
class UrdfRobotRuns : public ::testing::TestWithParam<RobotCase> {};

TEST_P(UrdfRobotRuns, TwoSecondsOnTheGroundWithoutDivergence) {
  const Scene scene = loadRobot(GetParam().file);
  RunOptions options;
  options.settings = scene.run;
  options.settings.duration = 2.0;
  State final;
  const RunReport report = runScene(scene, options, &final);
  EXPECT_EQ(report.status, "ok") << report.failure;
  EXPECT_NEAR(report.simulatedTime, 2.0, 1e-9);
  for (const Vec3& p : final.position) ASSERT_TRUE(isFinite(p));
}

std::string caseName(const ::testing::TestParamInfo<RobotCase>& param) {
  std::string name = param.param.file;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}
INSTANTIATE_TEST_SUITE_P(Shared, UrdfRobots, ::testing::ValuesIn(kCases), caseName);
// Every shipped robot runs its 2 s (0.2-0.6 s wall each, 2026-12-02). R2D2 did not
// finish in 60 s of wall time while its wheels' servos read the joint on a rim particle
// that the ground pushed (MODEL §1.7: the servos read the bodies now); 2 s in 5.2 s wall
// on a loaded machine since.
INSTANTIATE_TEST_SUITE_P(Slow, UrdfRobotRuns, ::testing::ValuesIn(kCases), caseName);

TEST(UrdfImport, ZeroMassOnAMovingLinkIsRefused) {
  try {
    build::makeUrdfRobot({.path = kBroken + "zero_mass.urdf"});
    FAIL();
  } catch (const build::UrdfError& e) {
    EXPECT_EQ(e.line(), 8) << e.what();
    EXPECT_NE(
        e.message().find("link 'arm' has mass 0 but moves (revolute joint 'shoulder', line 11)"),
        std::string::npos)
        << e.what();
  }
}

TEST(UrdfImport, FramesNotionalBaseAndLimits) {
  // The iiwa's link_0 (mass 0, fixed base) gets notional particles; the Panda's
  // link8 (no mass, fixed joint) is a frame of link7.
  const build::UrdfRobot iiwa = build::makeUrdfRobot({.path = kRobots + "/kuka_iiwa/model.urdf"});
  EXPECT_TRUE(iiwa.links[0].notional);
  EXPECT_EQ(iiwa.objects[0].name, "lbr_iiwa.lbr_iiwa_link_0");
  EXPECT_EQ(iiwa.objects[0].kind, "link");
  EXPECT_TRUE(iiwa.objects[0].geometry.rigid);
  for (bool fixed : iiwa.objects[0].geometry.fixed) EXPECT_TRUE(fixed);
  EXPECT_DOUBLE_EQ(iiwa.joints[1].upper, 2.09439510239);
  EXPECT_DOUBLE_EQ(iiwa.joints[1].effort, 300.0);
  EXPECT_EQ(iiwa.joints[1].modelJoint, "lbr_iiwa.lbr_iiwa_joint_2");
  EXPECT_THROW(
      build::makeUrdfRobot({.path = kRobots + "/kuka_iiwa/model.urdf", .fixedBase = false}),
      build::UrdfError);

  const build::UrdfRobot panda = build::makeUrdfRobot(
      {.path = kRobots + "/franka_panda/panda.urdf", .packagePaths = {kRobots + "/franka_panda"}});
  int frames = 0;
  for (std::size_t l = 0; l < panda.links.size(); ++l) {
    const build::UrdfLink& link = panda.links[l];
    if (link.attachedTo != static_cast<int>(l)) {
      ++frames;
      EXPECT_EQ(link.object, panda.links[static_cast<std::size_t>(link.attachedTo)].object);
    }
  }
  EXPECT_EQ(frames, 2);  // panda_link8, panda_grasptarget
  const auto mimic = std::find_if(panda.joints.begin(), panda.joints.end(),
                                  [](const auto& j) { return j.name == "panda_finger_joint2"; });
  ASSERT_NE(mimic, panda.joints.end());
  EXPECT_TRUE(mimic->hasMimic);
  EXPECT_EQ(mimic->mimicJoint, "panda_finger_joint1");
  EXPECT_DOUBLE_EQ(mimic->multiplier, 1.0);
  // No two links of a robot touch (selfCollision off): its link objects are one
  // contact group (noContactWithin), not every pair listed.
  int n = 0;  // links (their carriers, kind "virtual", touch nothing anyway)
  for (const auto& object : panda.objects) n += object.kind == "link" ? 1 : 0;
  EXPECT_EQ(panda.noContactWithin, n);
  EXPECT_TRUE(panda.noContact.empty());
}

TEST(UrdfImport, InitialPositionsAreTheJointPositionsAsBuilt) {
  build::UrdfSpec spec{.path = kRobots + "/kuka_iiwa/model.urdf"};
  spec.initialPositions = {{"lbr_iiwa_joint_2", 0.7}, {"lbr_iiwa_joint_4", -1.2}};
  const build::UrdfRobot robot = build::makeUrdfRobot(spec);
  build::ModelBuilder builder;
  build::placeUrdfRobot(builder, robot);
  const build::BuiltModel built = std::move(builder).build();
  EXPECT_NEAR(jointPosition(built.model, built.initial, 1), 0.7, 1e-9);
  EXPECT_NEAR(jointPosition(built.model, built.initial, 3), -1.2, 1e-9);
  EXPECT_NEAR(jointPosition(built.model, built.initial, 0), 0.0, 1e-9);
  spec.initialPositions = {{"lbr_iiwa_joint_2", 3.0}};
  EXPECT_THROW(build::makeUrdfRobot(spec), build::SpecError);
}

}  // namespace
}  // namespace robophi
