#pragma once
// Small file helpers shared by the tests.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace robophi::testing {

/// The shared robot descriptions (ROBOPHI_ROBOTS_DIR, tests/CMakeLists.txt).
inline const std::string kRobots = ROBOPHI_ROBOTS_DIR;

/// The whole content of a text file ("" if it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A new folder under the system's temporary folder, `prefix` and a random number.
inline std::filesystem::path makeTempFolder(const std::string& prefix) {
  std::random_device seed;
  const auto dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(seed()));
  std::filesystem::create_directories(dir);
  return dir;
}

/// The URDFs of ../shared/robots (under `robots`, ROBOPHI_ROBOTS_DIR) and of
/// ../shared/robots-wild beside it, as the issues' must-shows name them.
inline std::vector<std::string> sharedRobotUrdfs(const std::string& robots) {
  std::vector<std::string> files;
  for (const char* f : {"cartpole/cartpole.urdf", "husky/husky.urdf", "pr2_gripper/pr2_gripper.urdf",
                        "r2d2/r2d2.urdf", "franka_panda/panda.urdf", "kuka_iiwa/model.urdf",
                        "kuka_iiwa/model_vr_limits.urdf", "kuka_iiwa/model_free_base.urdf",
                        "kuka_iiwa/model_for_sdf.urdf"})
    files.push_back(robots + "/" + f);
  for (const char* f : {"laikago_description/urdf/laikago.urdf",
                        "allegro_hand_description/urdf/allegro_right_hand.urdf",
                        "allegro_hand_description/urdf/allegro_left_hand.urdf",
                        "ur_description/urdf/ur5_joint_limited_robot.urdf",
                        "ur_description/urdf/ur5_robot.urdf", "ur_description/urdf/ur5_gripper.urdf",
                        "solo_description/robots/solo.urdf", "solo_description/robots/solo12.urdf"})
    files.push_back(robots + "/../robots-wild/example-robot-data/robots/" + f);
  return files;
}

/// Writes `text` to a file, replacing it.
inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

/// An ASCII STL of the box [0, a] × [0, b] × [0, c] (12 outward triangles).
inline std::string boxStl(double a, double b, double c) {
  const double v[8][3] = {{0, 0, 0}, {a, 0, 0}, {a, b, 0}, {0, b, 0},
                          {0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
  const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                            {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::string text = "solid box\n";
  for (const auto& f : faces) {
    text += "facet normal 0 0 0\nouter loop\n";
    for (const int k : f) {
      text += "vertex " + std::to_string(v[k][0]) + " " + std::to_string(v[k][1]) + " " +
              std::to_string(v[k][2]) + "\n";
    }
    text += "endloop\nendfacet\n";
  }
  return text + "endsolid box\n";
}

/// An OBJ of one planar polygon of `corners` corners (a circle): past
/// kMaxMeshFaceIndices, the shape of a fuzz finding that hung the triangulator.
inline std::string polygonObj(int corners) {
  std::string text;
  for (int k = 0; k < corners; ++k)
    text += "v " + std::to_string(std::cos(6.283185307 * k / corners)) + " " +
            std::to_string(std::sin(6.283185307 * k / corners)) + " 0\n";
  text += "f";
  for (int k = 1; k <= corners; ++k) text += " " + std::to_string(k);
  return text + "\n";
}

}  // namespace robophi::testing
