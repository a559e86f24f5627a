// libFuzzer target for the URDF importer with meshes (docs/robots.md): URDF
// text → loadUrdfFile, as `robophi validate ROBOT.urdf` loads it, with the
// particle importer and with the rigid one (--rigid); then, for models of up to
// 20000 particles, the stability estimate, the compiled model and one force
// evaluation, as run builds them.
// An input may carry a mesh file of its own after a marker line
//   <!-- robophi-fuzz-mesh EXT -->   (EXT: stl, obj or dae)
// whose bytes are written to fuzz_mesh.EXT beside the URDF, so that the
// fuzzer mutates mesh files as well as the URDF that names them.
// It runs in a work folder (ROBOPHI_FUZZ_URDF_DIR, made by scripts/fuzz.sh) that
// holds the shared robots' meshes where their URDFs look for them (meshes/,
// pkg/meshes for package://meshes, the grippers' STL files).
// What it asserts, beyond "no crash, no leak, no undefined behaviour, no hang":
// no exception escapes the load (the command line would exit 1: an internal
// error), a load either fails with at least one message or returns a model
// that compiles, and every message and name is valid UTF-8.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "fuzz_checks.h"
#include "robophi/scene/scene.h"

namespace {

[[noreturn]] void failed(const char* what, const std::string& detail) {
  robophi::fuzz::failed("fuzz_urdf", what, detail);
}

void write(const std::string& path, const char* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data, static_cast<std::streamsize>(size));
  if (!out) failed("cannot write the work file", path);
}

// One load, checked as the command line would report it.
void load(const robophi::UrdfSceneOptions& options) {
  robophi::SceneLoadResult result;
  try {
    result = robophi::loadUrdfFile("fuzz.urdf", options);
  } catch (const std::exception& e) {
    failed("an exception escaped the load (robophi would exit 1)", e.what());
  }
  for (const robophi::Diagnostic& d : result.errors) {
    if (d.message.empty()) failed("an error without a message", d.format());
    (void)nlohmann::json(d.format()).dump();  // messages are UTF-8
  }
  for (const robophi::Diagnostic& d : result.warnings) (void)nlohmann::json(d.format()).dump();
  if (!result.ok()) {
    if (result.errors.empty()) failed("no scene and no error", "");
    return;
  }
  // Its names as JSON; built as validate and run build it (fuzz_checks.h).
  robophi::fuzz::checkLoadedScene("fuzz_urdf", *result.scene);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* dir = std::getenv("ROBOPHI_FUZZ_URDF_DIR");
  if (dir != nullptr && chdir(dir) != 0) failed("cannot enter ROBOPHI_FUZZ_URDF_DIR", dir);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  static const std::string kMarker = "<!-- robophi-fuzz-mesh ";
  std::size_t urdfSize = size;
  std::remove("fuzz_mesh.stl");
  std::remove("fuzz_mesh.obj");
  std::remove("fuzz_mesh.dae");
  if (const std::size_t at = text.find(kMarker); at != std::string::npos) {
    urdfSize = at;
    const std::size_t extension = at + kMarker.size();
    const std::size_t end = text.find('\n', extension);
    const std::string kind = text.substr(extension, 3);
    if (end != std::string::npos && (kind == "stl" || kind == "obj" || kind == "dae"))
      write("fuzz_mesh." + kind, text.data() + end + 1, size - end - 1);
  }
  write("fuzz.urdf", text.data(), urdfSize);
  robophi::UrdfSceneOptions options;
  options.packagePaths = {"pkg"};
  options.particlesPerLink = 8;  // (the default 30 is slow instrumented; the same roads)
  load(options);
  options.rigid = true;
  load(options);
  return 0;
}
