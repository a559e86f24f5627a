#pragma once
// The subcommands of the robophi program, one file each.

#include <CLI/CLI.hpp>

namespace robophi::cli {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
/// The scene file, the command line or another input has errors, or the
/// results folder holds files robophi did not write.
inline constexpr int kExitBadInput = 2;
/// The run diverged (NaN or infinite state) or stalled.
inline constexpr int kExitDiverged = 3;
/// The run ended well but a robotics goal was not reached (docs/robotics.md;
/// summary.json "events" says which, and how far).
inline constexpr int kExitGoalNotReached = 4;
/// Ended by SIGINT or SIGTERM: 128 + the signal (130, 143), exitCodeForSignal
/// in run/interrupt.h; the results so far are written.

void addRunCommand(CLI::App& app, int& exitCode);
void addValidateCommand(CLI::App& app, int& exitCode);
void addBenchCommand(CLI::App& app, int& exitCode);
void addStudyCommand(CLI::App& app, int& exitCode);
void addExportCommand(CLI::App& app);

}  // namespace robophi::cli
