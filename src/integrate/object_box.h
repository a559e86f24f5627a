#pragma once
// The boxes of approachStepFloor (robophi/adaptive_step.h): one pass over an
// object's particles, on AVX2 where the processor has it, else scalar; the two
// give the same boxes (tests/integrate/test_approach_floor.cpp).

#include <limits>
#include <vector>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi::detail {

/// An object's particles boxed: positions, velocities and accelerations, the
/// sum of the positions (in particle order, as approachStepBound sums them), the
/// count, the smallest and largest radius, and whether any particle is free (the
/// environment bounds only those).
struct ObjectBox {
  Vec3 pLow, pHigh, vLow, vHigh, aLow, aHigh, pSum;
  double count = 0.0, smallestRadius = std::numeric_limits<double>::infinity(), largestRadius = 0.0;
  bool anyFree = false;
  /// Empty again: what boxRun reads of an empty box (it sets the bounds from
  /// the first particle), cheaper than assigning a whole new box.
  void clear() {
    pSum = Vec3{};
    count = 0.0;
    smallestRadius = std::numeric_limits<double>::infinity();
    largestRadius = 0.0;
    anyFree = false;
  }
};

/// Adds particles [begin, end) to `box` (an acceleration is force / mass, 0 for
/// a fixed particle); returns the sum of all their numbers (not finite when one
/// is not: min and max would drop a NaN).
double boxRun(const Model& model, const State& state, const std::vector<Vec3>& force,
              ParticleIndex begin, ParticleIndex end, ObjectBox& box);

#if defined(__x86_64__) && defined(__GNUC__)
/// boxRun with a Vec3 in each AVX register (x, y, z; the fourth lane 0): the
/// same boxes and sums (min and max are exact, the sums lane by lane in particle
/// order; the zeros of min and max may differ in sign, which no bound sees).
/// Only where haveBoxRunLanes().
double boxRunLanes(const Model& model, const State& state, const std::vector<Vec3>& force,
                   ParticleIndex begin, ParticleIndex end, ObjectBox& box);
#endif

/// Whether boxRunLanes can run here (AVX2, checked once at run time).
bool haveBoxRunLanes();

}  // namespace robophi::detail
