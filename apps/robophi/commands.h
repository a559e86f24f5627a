#pragma once
// The subcommands of the robophi program, one file each.

#include <CLI/CLI.hpp>
#include <string>

#include "run/runner.h"

namespace robophi::cli {

/// Exit codes shared by every subcommand.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
/// The scene file, the command line or another input has errors, or the
/// results folder holds files robophi did not write.
inline constexpr int kExitBadInput = 2;
/// The run diverged (NaN or infinite state, runaway energy) or stalled.
inline constexpr int kExitDiverged = 3;
/// The run's energy account drifted past its bound (summary.json
/// "status": "energy_account_broken").
inline constexpr int kExitEnergyAccount = 4;
/// A goal of the scene was not reached by the end ("status": "goal_not_reached").
inline constexpr int kExitGoalNotReached = 5;
/// Ended by SIGINT or SIGTERM: 128 + the signal (130, 143), exitCodeForSignal
/// in run/interrupt.h; the results so far are written.

/// Prints a run's one-line result (and its error) and returns its exit code
/// (docs/output-format.md "Exit codes").
int reportRun(const std::string& label, const RunOptions& options, const RunReport& report);

void addRunCommand(CLI::App& app, int& exitCode);
void addResumeCommand(CLI::App& app, int& exitCode);
void addValidateCommand(CLI::App& app, int& exitCode);
void addInfoCommand(CLI::App& app, int& exitCode);
void addBenchCommand(CLI::App& app, int& exitCode);
void addStudyCommand(CLI::App& app, int& exitCode);
void addSweepCommand(CLI::App& app, int& exitCode);
void addExportCommand(CLI::App& app);

}  // namespace robophi::cli
