#pragma once
// Loading the scenes of scenes/ in the robotics tests.

#include <gtest/gtest.h>

#include <string>

#include "robophi/scene/scene.h"

namespace robophi::testing {

/// scenes/<name>, loaded; each loader error is a test failure.
inline Scene loadSceneFromScenes(const std::string& name) {
  SceneLoadResult result = loadSceneFile(std::string(ROBOPHI_SOURCE_DIR) + "/scenes/" + name);
  for (const auto& e : result.errors) ADD_FAILURE() << e.format();
  if (!result.ok()) return Scene{};
  return std::move(*result.scene);
}

}  // namespace robophi::testing
