// URDF import in time linear in its links, within stated budgets (issue 40: a
// chain of 5 000 fixed links took 124 s, the subtree lists were walked anew per
// joint; 20 000 revolute links passed 2.7 GB instead of being refused).
#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "robophi/build/urdf.h"
#include "robophi/scene/scene.h"
#include "test_files.h"

namespace robophi {
namespace {

namespace fs = std::filesystem;

// A tree of links of 0.1 kg, each a 2 cm box, link i's parent parent[i] (-1: the
// root), joined by `type` joints in the order of their children.
std::string treeUrdf(const std::vector<int>& parent, const std::string& type) {
  const auto links = static_cast<int>(parent.size());
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
  std::vector<int> siblings(parent.size(), 0);  // children placed so far, a link
  for (int i = 0; i < links; ++i) {
    const int p = parent[static_cast<std::size_t>(i)];
    if (p < 0) continue;
    // Each child 3 cm along x from its parent, siblings 3 cm apart along y.
    const int k = siblings[static_cast<std::size_t>(p)]++;
    text += "<joint name=\"j" + std::to_string(i) + "\" type=\"" + type + "\"><parent link=\"l" +
            std::to_string(p) + "\"/><child link=\"l" + std::to_string(i) +
            "\"/><origin xyz=\"0.03 " + (k == 0 ? std::string("0") : std::to_string(0.03 * k)) +
            " 0\"/>" + limit + "</joint>\n";
  }
  return text + "</robot>\n";
}

// A chain of `links` links.
std::string chainUrdf(int links, const std::string& type) {
  std::vector<int> parent;
  for (int i = 0; i < links; ++i) parent.push_back(i - 1);
  return treeUrdf(parent, type);
}

class UrdfBudget : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing::makeTempFolder("robophi_urdf_budget_"); }
  void TearDown() override { fs::remove_all(dir_); }

  SceneLoadResult load(int links, const std::string& type, int particlesPerLink,
                       bool rigid = false) {
    const fs::path file = dir_ / "chain.urdf";
    testing::writeText(file, chainUrdf(links, type));
    UrdfSceneOptions options;
    options.particlesPerLink = particlesPerLink;
    options.rigid = rigid;  // default: the budgets of the particle model
    return loadUrdfFile(file.string(), options);
  }
  static std::string errors(const SceneLoadResult& result) {
    std::string text;
    for (const Diagnostic& d : result.errors) text += d.format() + "\n";
    return text;
  }
  // The errors of a load that must be refused.
  std::string refusal(int links, const std::string& type, int particlesPerLink,
                      bool rigid = false) {
    const SceneLoadResult result = load(links, type, particlesPerLink, rigid);
    EXPECT_FALSE(result.ok());
    return errors(result);
  }

  fs::path dir_;
};

// 5 000 links, at the budget, load, in memory linear in the links: the links
// that never touch are one contact group (not their n²/2 pairs), and the weight
// lists (the bodies below each joint, n²/2 entries in all) are suffixes of one run.
TEST_F(UrdfBudget, AChainOf5000FixedLinksLoadsInLinearMemory) {
  const int n = build::kMaxUrdfBodies;
  const SceneLoadResult result = load(n, "fixed", 4);
  ASSERT_TRUE(result.ok()) << errors(result);
  const Scene& scene = *result.scene;
  ASSERT_EQ(scene.urdfRobots.size(), 1u);
  EXPECT_EQ(scene.urdfRobots[0]->links.size(), static_cast<std::size_t>(n));
  EXPECT_TRUE(scene.model.noContactPairs.empty());
  for (const ObjectInfo& object : scene.model.objects) {
    if (object.kind == "link") {
      EXPECT_EQ(object.contactGroup, scene.model.objects[0].contactGroup);
    }
  }
  EXPECT_GE(scene.model.objects[0].contactGroup, 0);
  const auto& links = scene.model.bodyLinks;
  ASSERT_EQ(links.size(), static_cast<std::size_t>(n - 1));
  for (std::size_t k = 0; k < links.size(); ++k) {
    // The link below joint k carries the bodies k + 1 .. n − 1, in order ...
    ASSERT_EQ(links[k].weightBodies.size(), static_cast<std::size_t>(n) - 1 - k);
    EXPECT_EQ(links[k].weightBodies[0], links[k].child);
    // ... the next link's list the rest of the same run.
    if (k + 1 < links.size()) {
      EXPECT_EQ(links[k + 1].weightBodies.begin(), links[k].weightBodies.begin() + 1);
    }
  }
}

// A tree's weight and subtree lists are each link's bodies in the order of a
// breadth-first walk of its subtree (the order the preload and the gravity
// effort sum them in), shared runs or lists of their own.
TEST_F(UrdfBudget, ATreesWeightListsAreBreadthFirstWalksOfItsSubtrees) {
  // parent of each link (-1: the root), children in this order.
  const std::vector<int> parent{-1, 0, 1, 1, 3, 0, 5, 6, 6, 0, 9, 10, 10, 11};
  const auto count = static_cast<int>(parent.size());
  const std::string text = treeUrdf(parent, "revolute");
  const fs::path file = dir_ / "tree.urdf";
  testing::writeText(file, text);
  UrdfSceneOptions options;
  options.particlesPerLink = 4;
  options.rigid = false;  // the particle model's body links
  const SceneLoadResult result = loadUrdfFile(file.string(), options);
  ASSERT_TRUE(result.ok()) << errors(result);
  const Model& model = result.scene->model;
  // Body of each link, by its name.
  std::vector<std::int32_t> bodyOf(parent.size(), -1);
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    for (int i = 0; i < count; ++i) {
      const std::string name = "l" + std::to_string(i);
      const std::string& body = model.bodies[b].name;
      if (body == name ||
          (body.size() > name.size() &&
           body.compare(body.size() - name.size() - 1, std::string::npos, "." + name) == 0))
        bodyOf[static_cast<std::size_t>(i)] = static_cast<std::int32_t>(b);
    }
  const auto walk = [&](int top) {
    std::vector<std::int32_t> out;
    std::vector<int> queue{top};
    for (std::size_t q = 0; q < queue.size(); ++q) {
      out.push_back(bodyOf[static_cast<std::size_t>(queue[q])]);
      for (int i = 0; i < count; ++i)
        if (parent[static_cast<std::size_t>(i)] == queue[q]) queue.push_back(i);
    }
    return out;
  };
  ASSERT_EQ(model.bodyLinks.size(), parent.size() - 1);
  std::size_t checked = 0;
  for (const BodyLink& link : model.bodyLinks) {
    int top = -1;
    for (int i = 0; i < count; ++i)
      if (bodyOf[static_cast<std::size_t>(i)] == link.child) top = i;
    ASSERT_GE(top, 0);
    const std::vector<std::int32_t> got(link.weightBodies.begin(), link.weightBodies.end());
    EXPECT_EQ(got, walk(top)) << "link l" << top;
    ++checked;
  }
  for (const Joint& joint : model.joints) {
    if (joint.subtreeBodies.empty()) continue;
    int top = -1;
    for (int i = 0; i < count; ++i)
      if (bodyOf[static_cast<std::size_t>(i)] == joint.subtreeBodies[0]) top = i;
    ASSERT_GE(top, 0);
    const std::vector<std::int32_t> got(joint.subtreeBodies.begin(), joint.subtreeBodies.end());
    EXPECT_EQ(got, walk(top)) << joint.name;
    ++checked;
  }
  EXPECT_GT(checked, parent.size() - 1);  // every body link, and the joints
}

// Past the budget of links with particles: refused at once, naming the count.
TEST_F(UrdfBudget, TwentyThousandRevoluteLinksAreRefusedByTheBudget) {
  const std::string text = refusal(20000, "revolute", 30);
  EXPECT_NE(text.find("chain.urdf:5002: error: 20000 links carry particles, more than the budget "
                      "of 5000 links of a robot (docs/scene-format.md#limits): link 'l5000' is "
                      "the first past it"),
            std::string::npos)
      << text;
}

// As rigid bodies too: refused at the joint that passes the budget, naming it and
// its line (the URDF has a line a link, then a line a joint, after the <robot> line).
TEST_F(UrdfBudget, TwentyThousandRevoluteLinksAreRefusedByTheBudgetAsRigidBodies) {
  const std::string text = refusal(20000, "revolute", 30, true);
  EXPECT_NE(text.find("chain.urdf:25002: error: joint 'j5001' makes link 'l5001' moving body 5001, "
                      "more than the budget of 5000 moving links of a robot"),
            std::string::npos)
      << text;
}

// A rigid robot's primitive shape past the particle budget of an object (a disc
// of 803 m radius, 0.2 m thick: 8e8 surface particles of 0.1 m, 14 GB and a hang
// in the fuzz target) is refused before its particles are made, naming the body.
TEST_F(UrdfBudget, ARigidDiscPastTheParticleBudgetIsRefusedBeforeItIsFilled) {
  const fs::path file = dir_ / "disc.urdf";
  testing::writeText(file,
                     "<robot name=\"disc\"><link name=\"plate\"><inertial><mass value=\"1\"/>"
                     "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/>"
                     "</inertial><collision><geometry><cylinder radius=\"803\" length=\"0.2\"/>"
                     "</geometry></collision></link></robot>\n");
  UrdfSceneOptions options;
  options.rigid = true;
  const SceneLoadResult result = loadUrdfFile(file.string(), options);
  ASSERT_FALSE(result.ok());
  const std::string text = errors(result);
  EXPECT_NE(text.find("disc.urdf: error: UrdfMultibodyPlacement: the collision shape of body "
                      "'disc.plate' would make about"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("more than the budget of 250000 particles of an object"), std::string::npos)
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
