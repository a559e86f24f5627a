// robophi export html|vtk|png DIR: a finished run folder as a replay page, a
// ParaView time series, or a picture of the page at a moment (docs/viewer.md).
// Exit 0 on success, 1 on failure, with the message naming the file and what is
// wrong.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

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

// The headless Chromium to shoot a page with: $ROBOPHI_CHROMIUM, else the first of
// chromium, chromium-browser, google-chrome on the PATH; empty when there is none.
std::string findChromium() {
  if (const char* given = std::getenv("ROBOPHI_CHROMIUM"); given != nullptr && *given != '\0')
    return given;
  const char* path = std::getenv("PATH");
  std::string folders = path != nullptr ? path : "/usr/bin:/bin";
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::size_t start = 0;
    while (start <= folders.size()) {
      const std::size_t end = std::min(folders.find(':', start), folders.size());
      const std::filesystem::path candidate =
          std::filesystem::path(folders.substr(start, end - start)) / name;
      if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
      start = end + 1;
    }
  }
  return {};
}

// Runs `argv` (no shell) and returns its exit status, -1 when it could not start.
int runProgram(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t child = ::fork();
  if (child < 0) return -1;
  if (child == 0) {
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  if (::waitpid(child, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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

  // robophi export png DIR --time T: the replay page at model time T (its #t=T
  // address) shot by headless Chromium, the page written first when it is missing.
  struct PngArgs {
    std::string runDir;
    std::string out;
    double time = 0.0;
    int width = 1400, height = 820;
  };
  auto png = std::make_shared<PngArgs>();
  auto* pngCmd = cmd->add_subcommand(
      "png", "Picture the replay page at a moment (needs headless Chromium)");
  pngCmd->add_option("DIR", png->runDir, "Run folder (written by robophi run)")->required();
  pngCmd->add_option("--time", png->time, "Model time to show (s; the frame at or before it)");
  pngCmd->add_option("--out", png->out, "Output file (default DIR/replay-T.png)");
  pngCmd->add_option("--width", png->width, "Picture width (px)")->check(CLI::PositiveNumber);
  pngCmd->add_option("--height", png->height, "Picture height (px)")->check(CLI::PositiveNumber);
  pngCmd->callback([png] {
    const std::string chromium = findChromium();
    if (chromium.empty()) {
      fail("no headless Chromium found (looked at $ROBOPHI_CHROMIUM, then chromium, "
           "chromium-browser, google-chrome on the PATH): install one (apt-get install "
           "chromium), or open DIR/replay.html#t=" + fmt::format("{}", png->time) +
           " in a browser");
    }
    const std::filesystem::path page =
        std::filesystem::absolute(std::filesystem::path(png->runDir) / "replay.html");
    if (!std::filesystem::exists(page)) {
      const auto lock = lockRunFolder(png->runDir);
      std::string error;
      if (!writeReplayHtml(png->runDir, ReplayOptions{}, error)) fail(error);
    }
    const std::string out =
        png->out.empty()
            ? (std::filesystem::path(png->runDir) / fmt::format("replay-{}.png", png->time)).string()
            : png->out;
    const std::string address = "file://" + page.string() + fmt::format("#t={}", png->time);
    // The virtual time budget lets the page load, parse its meshes and draw first.
    const int status = runProgram(
        {chromium, "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
         "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--hide-scrollbars",
         "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", "--virtual-time-budget=20000",
         fmt::format("--window-size={},{}", png->width, png->height),
         "--screenshot=" + std::filesystem::absolute(out).string(), address});
    if (status != 0 || !std::filesystem::exists(out))
      fail(fmt::format("{} did not write {} (exit status {})", chromium, out, status));
    std::printf("wrote %s\n", out.c_str());
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
