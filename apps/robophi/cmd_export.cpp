// robophi export html|vtk DIR: a finished run folder as a replay page or a
// ParaView time series (docs/viewer.md). Exit 0 on success, 1 on failure, with
// the message naming the file and what is wrong.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "commands.h"
#include "output/replay.h"
#include "output/results_folder.h"
#include "output/results_lock.h"
#include "output/vtk_export.h"

namespace robophi::cli {

namespace {

// main() returns the exit code of a CLI::RuntimeError without printing, so the
// message goes to stderr here.
[[noreturn]] void fail(const std::string& error, int exitCode = kExitFailure) {
  std::fprintf(stderr, "robophi export: error: %s\n", error.c_str());
  throw CLI::RuntimeError(exitCode);
}

// The run folder's lock (output/results_lock.h), held while the export reads it
// and writes into it: a run replacing the folder meanwhile is refused, and a
// folder a run is writing is not exported (exit 2).
std::optional<output::ResultsFolderLock> lockRunFolder(const std::string& runDir) {
  try {
    return std::optional<output::ResultsFolderLock>(std::in_place, runDir);
  } catch (const output::ResultsFolderError& e) {
    fail(e.what(), kExitBadInput);
  }
}

}  // namespace

void addExportCommand(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("export", "Turn a run folder into a replay page or ParaView files");
  cmd->require_subcommand(1);

  struct HtmlArgs {
    std::string runDir;
    std::string out;
    double sizeCapMb = 50.0;
  };
  auto html = std::make_shared<HtmlArgs>();
  auto* htmlCmd = cmd->add_subcommand(
      "html", "Write a self-contained replay page (opens from disk, no server needed)");
  htmlCmd->add_option("DIR", html->runDir, "Run folder (written by robophi run)")->required();
  htmlCmd->add_option("--out", html->out, "Output file (default DIR/replay.html)");
  htmlCmd
      ->add_option("--size-cap-mb", html->sizeCapMb,
                   "Largest page size (MB); frames are decimated to fit")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  htmlCmd->callback([html] {
    const auto lock = lockRunFolder(html->runDir);
    ReplayOptions options;
    options.sizeCapBytes = html->sizeCapMb * 1e6;
    options.outputPath = html->out;
    std::string error;
    if (!writeReplayHtml(html->runDir, options, error)) fail(error);
    const std::string written = html->out.empty()
                                    ? (std::filesystem::path(html->runDir) / "replay.html").string()
                                    : html->out;
    std::printf("wrote %s\n", written.c_str());
  });

  struct VtkArgs {
    std::string runDir;
    std::string out;
  };
  auto vtk = std::make_shared<VtkArgs>();
  auto* vtkCmd =
      cmd->add_subcommand("vtk", "Write ParaView files: one .vtp per frame and a .pvd collection");
  vtkCmd->add_option("DIR", vtk->runDir, "Run folder (written by robophi run)")->required();
  vtkCmd->add_option("--out", vtk->out, "Output folder (default DIR/vtk)");
  vtkCmd->callback([vtk] {
    const auto lock = lockRunFolder(vtk->runDir);
    const std::string outDir =
        vtk->out.empty() ? (std::filesystem::path(vtk->runDir) / "vtk").string() : vtk->out;
    std::string error;
    if (!writeVtkSeries(vtk->runDir, outDir, error)) fail(error);
    std::printf("wrote %s\n", (std::filesystem::path(outDir) / "run.pvd").string().c_str());
  });
}

}  // namespace robophi::cli
