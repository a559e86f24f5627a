#pragma once
/// \file
/// Checks of a scene's initial state before it runs: objects that start
/// interpenetrating (each other or the environment) are thrown apart by the
/// contact force at the first step, so the run says so (summary.json "warnings",
/// robophi run's stderr).

#include <string>
#include <vector>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// An overlap deeper than this fraction of the smaller radius involved (-) is
/// reported; resting contacts (a few per cent under gravity) are not.
inline constexpr double kStartingOverlapFraction = 0.05;

/// One warning per pair of objects (or object and environment item) whose
/// particles start overlapping by more than kStartingOverlapFraction of the
/// smaller radius: names both, the deepest penetration (m and fraction of the
/// radius), its particles and how many pairs overlap. Virtual objects (goals,
/// paths) are left out. Empty when contact is off or nothing overlaps.
std::vector<std::string> startingOverlapWarnings(const Model& model, const State& initial);

}  // namespace robophi
