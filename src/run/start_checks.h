#pragma once
/// \file
/// Checks of a scene's initial state before it runs: objects that start
/// interpenetrating (each other or the environment) are thrown apart by the
/// contact force at the first step, so the run says so (summary.json "warnings",
/// robophi run's stderr).

#include <cstddef>
#include <string>
#include <vector>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// An overlap deeper than this fraction of the smaller radius involved (-) is
/// reported; resting contacts (a few per cent under gravity) are not.
inline constexpr double kStartingOverlapFraction = 0.05;

/// At most this many overlap warnings name their objects; one more counts the rest.
inline constexpr std::size_t kMaxOverlapWarnings = 5;

/// One warning per pair of objects (or object and environment item, or object
/// with itself: particles of one object not tied by a connector) whose
/// particles start overlapping by more than kStartingOverlapFraction of the
/// smaller radius: names both, the deepest penetration (m and fraction of the
/// radius), its particles and how many pairs overlap; the pairs with the most
/// overlapping particles first, at most kMaxOverlapWarnings of them and a line
/// that counts the others. Virtual objects (goals, paths) are left out. Empty
/// when contact is off or nothing overlaps.
std::vector<std::string> startingOverlapWarnings(const Model& model, const State& initial);

}  // namespace robophi
