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
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz_checks.h"
#include "robophi/scene/scene.h"

namespace {

[[noreturn]] void failed(const char* what, const std::string& detail) {
  robophi::fuzz::failed("fuzz_scene", what, detail);
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
  // Its names as JSON; built as validate and run build it (fuzz_checks.h).
  robophi::fuzz::checkLoadedScene("fuzz_scene", *result.scene);
  return 0;
}
