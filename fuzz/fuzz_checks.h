#pragma once
// What both fuzz targets check of a scene that loaded (fuzz_scene.cpp,
// fuzz_urdf.cpp): its names dump as JSON (they reach model.json and joints.csv:
// valid UTF-8), and, for models of up to 20000 particles, it builds as
// `robophi validate` and `robophi run` build it: the stability estimate, the
// compiled model (which throws on an inconsistent model) and one force pass.
// (A model at the size budget takes 1-2 s in a release build but over 30 s
// instrumented, which libFuzzer would report as a hang; the loaders themselves
// run on every input.)
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/compiled_model.h"
#include "robophi/evaluation.h"
#include "robophi/scene/scene.h"
#include "robophi/stability.h"

namespace robophi::fuzz {

[[noreturn]] inline void failed(const char* target, const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s: %s: %s\n", target, what, detail.c_str());
  std::abort();
}

inline void checkLoadedScene(const char* target, const Scene& scene) {
  nlohmann::json names = nlohmann::json::array({scene.name, scene.description});
  for (const auto& object : scene.model.objects) names.push_back(object.name);
  for (const auto& joint : scene.model.joints) names.push_back(joint.name);
  for (const auto& material : scene.model.materials) names.push_back(material.name);
  (void)names.dump();
  if (scene.model.particleCount() > 20000) return;
  const StabilityEstimate stability = estimateStability(scene.model, &scene.initial.position);
  if (!(stability.omegaMax >= 0.0))
    failed(target, "omega_max is not >= 0", std::to_string(stability.omegaMax));
  const CompiledModel compiled(scene.model);
  Workspace workspace;
  (void)evaluate(compiled, scene.initial, workspace);
}

}  // namespace robophi::fuzz
