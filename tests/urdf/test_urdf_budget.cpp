// URDF import in time linear in its links, within stated budgets (issue 40: a
// chain of 5 000 fixed links took 124 s, the subtree lists were walked anew per
// joint; 20 000 revolute links passed 2.7 GB instead of being refused).
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <string>

#include "robophi/build/urdf.h"
#include "robophi/scene/scene.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

// A chain of `links` links of 0.1 kg, each a 2 cm box, joined by `type` joints.
std::string chainUrdf(int links, const std::string& type) {
  std::string text = "<robot name=\"chain\">\n";
  for (int i = 0; i < links; ++i)
    text += "<link name=\"l" + std::to_string(i) +
            "\"><inertial><mass value=\"0.1\"/><inertia ixx=\"1e-4\" iyy=\"1e-4\" izz=\"1e-4\" "
            "ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial><collision><geometry><box size=\"0.02 "
            "0.02 0.02\"/></geometry></collision></link>\n";
  const std::string limit = type == "revolute"
                                ? "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" "
                                  "effort=\"1\" velocity=\"1\"/>"
                                : "";
  for (int i = 1; i < links; ++i)
    text += "<joint name=\"j" + std::to_string(i) + "\" type=\"" + type + "\"><parent link=\"l" +
            std::to_string(i - 1) + "\"/><child link=\"l" + std::to_string(i) +
            "\"/><origin xyz=\"0.03 0 0\"/>" + limit + "</joint>\n";
  return text + "</robot>\n";
}

class UrdfBudget : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::makeTempFolder("robophi_urdf_budget_"); }
  void TearDown() override { fs::remove_all(dir_); }

  SceneLoadResult load(int links, const std::string& type, int particlesPerLink) {
    const fs::path file = dir_ / "chain.urdf";
    testing::writeText(file, chainUrdf(links, type));
    UrdfSceneOptions options;
    options.particlesPerLink = particlesPerLink;
    options.rigid = false;  // budgets of the particle model
    return loadUrdfFile(file.string(), options);
  }
  static std::string errors(const SceneLoadResult& result) {
    std::string text;
    for (const Diagnostic& d : result.errors) text += d.format() + "\n";
    return text;
  }
  // The errors of a load that must be refused.
  std::string refusal(int links, const std::string& type, int particlesPerLink) {
    const SceneLoadResult result = load(links, type, particlesPerLink);
    EXPECT_FALSE(result.ok());
    return errors(result);
  }

  fs::path dir_;
};

// 5 000 links, at the budget, load. The lists the model keeps are their square
// and no more: every pair of links that never touch once, and each link's
// weight list (the bodies below it) once per joint.
TEST_F(UrdfBudget, AChainOf5000FixedLinksLoads) {
  const int n = build::kMaxUrdfBodies;
  const SceneLoadResult result = load(n, "fixed", 4);
  ASSERT_TRUE(result.ok()) << errors(result);
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.urdfRobots.size(), 1u);
  EXPECT_EQ(scene.urdfRobots[0]->links.size(), static_cast<std::size_t>(n));
  const auto pairs = static_cast<std::size_t>(n) * (n - 1) / 2;
  EXPECT_EQ(scene.model.noContactPairs.size(), pairs);
  std::size_t weights = 0;
  for (const BodyLink& link : scene.model.bodyLinks) weights += link.weightBodies.size();
  EXPECT_EQ(scene.model.bodyLinks.size(), static_cast<std::size_t>(n - 1));
  EXPECT_EQ(weights, pairs);  // the link below joint k carries n - k bodies
}

// Past the budget of links with particles: refused at once, naming the count.
TEST_F(UrdfBudget, TwentyThousandRevoluteLinksAreRefusedByTheBudget) {
  const std::string text = refusal(20000, "revolute", 30);
  EXPECT_NE(text.find("chain.urdf: error: 20000 links carry particles, more than the budget of "
                      "5000 links of a robot"),
            std::string::npos)
      << text;
}

// Within the link budget but past the particles': refused before a link is filled.
TEST_F(UrdfBudget, LinksTimesParticlesPerLinkPastTheParticleBudgetAreRefused) {
  const std::string text = refusal(3000, "revolute", 100);
  EXPECT_NE(text.find("3000 links of about 100 particles (particlesPerLink) make more than the "
                      "budget of 250000 particles"),
            std::string::npos)
      << text;
}

// Within the link and particle budgets but past the connectors' (a scene's, which the
// scene loader holds a {"type": "urdf"} object to): a bare URDF (robophi run ROBOT.urdf
// --particles) is refused as its links are filled, naming the file and the link,
// before a model is built (it was built: 2 000 links of 100 particles, 1.4 million LS).
TEST_F(UrdfBudget, LinksPastTheConnectorBudgetAreRefusedBeforeTheModelIsBuilt) {
  const std::string text = refusal(2000, "revolute", 100);
  EXPECT_NE(text.find("chain.urdf:"), std::string::npos) << text;
  EXPECT_NE(text.find("connectors, more than the budget of 1000000"), std::string::npos) << text;
}

}  // namespace
}  // namespace robophi
