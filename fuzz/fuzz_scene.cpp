// libFuzzer target for the scene loader (docs/scene-format.md): scene text →
// loadSceneText → the model compiled and its stability estimated, as
// `robophi validate` does, plus one force evaluation of the initial state (those
// three for models of up to 20000 particles).
// What it asserts, beyond "no crash, no leak, no undefined behaviour, no hang":
// a load either fails with at least one located message or returns a model that
// compiles, and every name it keeps is valid UTF-8 (it reaches model.json).
// Build and run: scripts/fuzz.sh (fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "robophi/compiled_model.h"
#include "robophi/evaluation.h"
#include "robophi/scene/scene.h"
#include "robophi/stability.h"

namespace {

[[noreturn]] void failed(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz_scene: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  robophi::SceneLoadResult result = robophi::loadSceneText(text, "fuzz.json");
  for (const robophi::Diagnostic& d : result.errors) {
    const std::string line = d.format();
    if (d.message.empty()) failed("an error without a message", line);
    // Messages go to a terminal and to files: they must be UTF-8 too.
    (void)nlohmann::json(line).dump();
  }
  if (!result.ok()) {
    if (result.errors.empty()) failed("no scene and no error", "");
    return 0;
  }
  const robophi::Scene& scene = *result.scene;
  // Every name the results carry (model.json, joints.csv) must dump as JSON.
  nlohmann::json names = nlohmann::json::array({scene.name, scene.description});
  for (const auto& object : scene.model.objects) names.push_back(object.name);
  for (const auto& joint : scene.model.joints) names.push_back(joint.name);
  for (const auto& material : scene.model.materials) names.push_back(material.name);
  (void)names.dump();

  // As validate: the stability estimate; as run: the compiled model and a force pass.
  // Only for models of up to 20000 particles: a model at the size budget takes
  // 1-2 s in a release build (robophi validate) but over 30 s instrumented, which
  // libFuzzer would report as a hang; the loader itself runs on every input.
  if (scene.model.particleCount() > 20000) return 0;
  const robophi::StabilityEstimate stability =
      robophi::estimateStability(scene.model, &scene.initial.position);
  if (!(stability.omegaMax >= 0.0))
    failed("omega_max is not >= 0", std::to_string(stability.omegaMax));
  const robophi::CompiledModel compiled(scene.model);  // throws on an inconsistent model
  robophi::Workspace workspace;
  (void)robophi::evaluate(compiled, scene.initial, workspace);
  return 0;
}
