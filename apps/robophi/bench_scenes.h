#pragma once
// The standard benchmark scenes, built in code so that they are exactly as specified.

#include <string>
#include <vector>

#include "robophi/scene/scene.h"

namespace robophi::cli {

/// A named benchmark scene.
struct BenchScene {
  std::string name;
  Scene scene;
  /// Run with the adaptive step capped at the scene's dt, so that it takes the
  /// same steps as the constant run and the per-step cost can be compared.
  bool adaptive = false;
  /// For an adaptive run: the constant-step scene it is compared with.
  std::string comparedWith;
};

/// CLOTH N: N×N particles 1 cm apart in z = 0, 1 kg in all, corners (0,0) and
/// (N-1,0) fixed; structural and shear LS of stiffness 1e4 N/m, damping
/// 0.2·sqrt(1e4·m); gravity -z; symplectic Euler, dt = 1e-4·32/N s, 1 s.
Scene makeClothScene(int n);

/// Two rigid lattice cubes of `cellsPerSide`³ particles each (no connectors: a
/// geometry benchmark), the second rotated 10° about x and pressed onto the
/// first's +x face by a fifth of a cell; both flagged ObjectInfo::rigid (their
/// sphere trees move as a whole) unless `rigid` is false; no pair list kept
/// (neighbourSkin 0), so that every evaluation searches the hierarchy.
Scene makeRigidPairScene(int cellsPerSide, bool rigid);

/// RIGID: contact detection cost for two rigid objects in contact from 10³ to
/// 10⁵ particles per object (node tests, pair tests, processor time per
/// evaluation; "moving": with one sliding and turning on the other), and
/// the log-log slopes of tests and time against n. Returns 0.
int runRigidScaling(bool json);

/// The standard set: CLOTH 32, 64, 128 and the example scenes. `quick` shortens
/// every run to a smoke test.
std::vector<BenchScene> standardBenchScenes(bool quick);

}  // namespace robophi::cli
