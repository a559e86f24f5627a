// robophi: the command-line program.
#include <cstdio>
#include <exception>

#include "commands.h"
#include "robophi/version.h"

int main(int argc, char** argv) {
  CLI::App app{"robophi: particle-based physical models of robots and their environment"};
  app.set_version_flag("--version", std::string("robophi ") + robophi::kVersion);
  app.require_subcommand(1);
  int exitCode = robophi::cli::kExitOk;
  robophi::cli::addRunCommand(app, exitCode);
  robophi::cli::addResumeCommand(app, exitCode);
  robophi::cli::addValidateCommand(app, exitCode);
  robophi::cli::addInfoCommand(app, exitCode);
  robophi::cli::addBenchCommand(app, exitCode);
  robophi::cli::addExportCommand(app);
  robophi::cli::addStudyCommand(app, exitCode);
  robophi::cli::addSweepCommand(app, exitCode);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {  // a subcommand's own exit code (robophi export)
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad command line is bad input (exit 2).
    return app.exit(e) == 0 ? robophi::cli::kExitOk : robophi::cli::kExitBadInput;
  } catch (const CLI::Error& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "robophi: error: %s\n", e.what());
    return robophi::cli::kExitFailure;
  }
  return exitCode;
}
