#pragma once
// The subcommands of the robophi program, one file each.

#include <CLI/CLI.hpp>

namespace robophi::cli {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
/// The scene file (or another input) has errors.
inline constexpr int kExitBadInput = 2;
/// The run diverged (NaN or infinite state).
inline constexpr int kExitDiverged = 3;

void addRunCommand(CLI::App& app, int& exitCode);
void addValidateCommand(CLI::App& app, int& exitCode);
void addBenchCommand(CLI::App& app, int& exitCode);
void addStudyCommand(CLI::App& app, int& exitCode);
void addExportCommand(CLI::App& app);

}  // namespace robophi::cli
