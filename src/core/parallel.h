#pragma once
// Deterministic parallel loops for the step's stages, on a pool of worker
// threads (parallel.cpp) that take chunks from a shared counter; the calling
// thread takes them too and waits only for chunks in progress. The work is cut into chunks of a
// fixed size that does not depend on the thread count, and every sum is taken inside a chunk in
// index order and then over the chunks in chunk order: the same bits for 1, 2, 4 or 8 threads. A
// range of one chunk sums exactly as a plain serial loop does.

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace robophi::detail {

/// The threads the machine offers (>= 1).
int availableThreads();

/// function(context, c) for c in [0, chunks), on up to `threads` threads (the
/// caller's among them); serially when the pool is busy with another job.
using ChunkFunction = void (*)(void* context, std::int64_t chunk);
void runChunks(int threads, std::int64_t chunks, ChunkFunction function, void* context);

/// first() and second() side by side on up to two threads (the caller takes
/// first(), then second() if no worker has taken it); one after the other on
/// one thread or when the pool is busy. For two jobs that write apart.
template <class First, class Second>
void runBoth(int threads, const First& first, const Second& second) {
  struct Context {
    const First* first;
    const Second* second;
  } context{&first, &second};
  runChunks(
      std::min(threads, 2), 2,
      [](void* raw, std::int64_t job) {
        const Context& x = *static_cast<const Context*>(raw);
        if (job == 0) {
          (*x.first)();
        } else {
          (*x.second)();
        }
      },
      &context);
}

/// Elements of a chunk: the grain of the parallel loops and of the sums.
inline constexpr std::int64_t kParallelChunk = 1024;
/// Below this many elements a stage runs on the calling thread (waking the
/// workers costs microseconds).
inline constexpr std::int64_t kParallelMinimum = 4 * kParallelChunk;

/// body(begin, end) for consecutive chunks of [0, count), on up to `threads`
/// threads. For element-wise work whose result does not depend on the order.
template <class Body>
void parallelFor(int threads, std::int64_t count, const Body& body) {
  const std::int64_t chunks = (count + kParallelChunk - 1) / kParallelChunk;
  struct Context {
    const Body* body;
    std::int64_t count;
  } context{&body, count};
  runChunks(
      count >= kParallelMinimum ? threads : 1, chunks,
      [](void* raw, std::int64_t c) {
        const Context& x = *static_cast<const Context*>(raw);
        (*x.body)(c * kParallelChunk, std::min(x.count, (c + 1) * kParallelChunk));
      },
      &context);
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
  struct Context {
    const Body* body;
    std::int64_t count;
    std::array<double, N> initial;
    std::array<double, N>* partial;
  } context{&body, count, initial, partial.data()};
  runChunks(
      count >= kParallelMinimum ? threads : 1, chunks,
      [](void* raw, std::int64_t c) {
        const Context& x = *static_cast<const Context*>(raw);
        std::array<double, N> sums{};
        if (c == 0) sums = x.initial;
        (*x.body)(c * kParallelChunk, std::min(x.count, (c + 1) * kParallelChunk), sums);
        x.partial[c] = sums;
      },
      &context);
  std::array<double, N> total = partial[0];
  for (std::size_t c = 1; c < partial.size(); ++c) {
    for (std::size_t k = 0; k < N; ++k) total[k] += partial[c][k];
  }
  return total;
}

}  // namespace robophi::detail
