#pragma once
// Deterministic parallel loops for the step's stages (OpenMP when the core is
// built with it, serial otherwise). The work is cut into chunks of a fixed
// size that does not depend on the thread count, and every sum is taken
// inside a chunk in index order and then over the chunks in chunk order: the
// same bits for 1, 2, 4 or 8 threads. A range of one chunk sums exactly as a
// plain serial loop does.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace robophi::detail {

/// The threads the machine offers (>= 1): OpenMP's default team size, or 1.
int availableThreads();

/// Elements of a chunk: the grain of the parallel loops and of the sums.
inline constexpr std::int64_t kParallelChunk = 1024;
/// Below this many elements a stage runs on the calling thread (a team costs
/// a few microseconds to start).
inline constexpr std::int64_t kParallelMinimum = 4 * kParallelChunk;

/// body(begin, end) for consecutive chunks of [0, count), on up to `threads`
/// threads. For element-wise work whose result does not depend on the order.
template <class Body>
void parallelFor(int threads, std::int64_t count, const Body& body) {
  const std::int64_t chunks = (count + kParallelChunk - 1) / kParallelChunk;
  const bool team = threads > 1 && count >= kParallelMinimum;
#pragma omp parallel for num_threads(threads) schedule(static) if (team)
  for (std::int64_t c = 0; c < chunks; ++c) {
    body(c * kParallelChunk, std::min(count, (c + 1) * kParallelChunk));
  }
}

/// N sums over [0, count): body(begin, end, sums) adds its elements' terms to
/// `sums` in index order. The first chunk starts from `initial`, the others
/// from zero, and the chunks' sums are added in chunk order, so the result is
/// independent of `threads` (and, for count <= kParallelChunk, equal to the
/// serial loop's).
template <std::size_t N, class Body>
std::array<double, N> parallelSum(int threads, std::int64_t count, std::array<double, N> initial,
                                  const Body& body) {
  const std::int64_t chunks = (count + kParallelChunk - 1) / kParallelChunk;
  if (chunks <= 1) {
    body(std::int64_t{0}, count, initial);
    return initial;
  }
  std::vector<std::array<double, N>> partial(static_cast<std::size_t>(chunks));
  const bool team = threads > 1 && count >= kParallelMinimum;
#pragma omp parallel for num_threads(threads) schedule(static) if (team)
  for (std::int64_t c = 0; c < chunks; ++c) {
    std::array<double, N> sums{};
    if (c == 0) sums = initial;
    body(c * kParallelChunk, std::min(count, (c + 1) * kParallelChunk), sums);
    partial[static_cast<std::size_t>(c)] = sums;
  }
  std::array<double, N> total = partial[0];
  for (std::size_t c = 1; c < partial.size(); ++c) {
    for (std::size_t k = 0; k < N; ++k) total[k] += partial[c][k];
  }
  return total;
}

}  // namespace robophi::detail
