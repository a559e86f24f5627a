// The step's thread pool (core/parallel.h): workers that take chunks from a
// shared ticket, so the calling thread never waits for a worker that has not
// started (on a busy machine a descheduled worker would stall every stage).
#include "core/parallel.h"

#include <atomic>
#include <chrono>
#include <thread>

namespace robophi::detail {

namespace {

// The ticket: generation (32 bits) | chunk count (16) | next chunk (16).
constexpr int kCountShift = 16;
constexpr std::uint64_t kIndexMask = 0xffff;
std::uint64_t generationOf(std::uint64_t t) { return t >> 32; }
std::uint64_t countOf(std::uint64_t t) { return (t >> kCountShift) & kIndexMask; }
std::uint64_t indexOf(std::uint64_t t) { return t & kIndexMask; }

class Pool {
 public:
  static Pool& instance() {
    static Pool* pool = new Pool;  // never destroyed: its workers sleep at exit
    return *pool;
  }

  // False when the pool is busy (another thread's job, or a job inside a job):
  // the caller then runs the chunks itself.
  bool run(int threads, std::int64_t chunks, ChunkFunction function, void* context) {
    if (chunks > static_cast<std::int64_t>(kIndexMask)) return false;
    if (busy_.exchange(true, std::memory_order_acquire)) return false;
    while (static_cast<int>(workers_.size()) < threads - 1 && workers_.size() < kMaxWorkers) {
      const int id = static_cast<int>(workers_.size());
      workers_.emplace_back([this, id] { workerLoop(id); });
    }
    function_ = function;
    context_ = context;
    helpers_.store(threads - 1, std::memory_order_relaxed);
    remaining_.store(chunks, std::memory_order_relaxed);
    generation_ = (generation_ + 1) & 0xffffffffu;
    if (generation_ == 0) generation_ = 1;  // 0: no job yet
    const std::uint64_t generation = generation_;
    ticket_.store((generation << 32) | (static_cast<std::uint64_t>(chunks) << kCountShift),
                  std::memory_order_release);
    ticket_.notify_all();
    takeChunks(generation);
    // Only chunks in progress on a worker are left.
    while (remaining_.load(std::memory_order_acquire) != 0) std::this_thread::yield();
    busy_.store(false, std::memory_order_release);
    return true;
  }

 private:
  static constexpr std::size_t kMaxWorkers = 255;

  // Claims and runs chunks of job `generation` until none is left.
  void takeChunks(std::uint64_t generation) {
    std::uint64_t t = ticket_.load(std::memory_order_acquire);
    while (generationOf(t) == generation && indexOf(t) < countOf(t)) {
      if (ticket_.compare_exchange_weak(t, t + 1, std::memory_order_acq_rel,
                                        std::memory_order_acquire)) {
        // Claimed: the job cannot change before this chunk is counted done.
        function_(context_, static_cast<std::int64_t>(indexOf(t)));
        remaining_.fetch_sub(1, std::memory_order_acq_rel);
        t = ticket_.load(std::memory_order_acquire);
      }
    }
  }

  void workerLoop(int id) {
    std::uint64_t handled = 0;  // the last generation this worker looked at
    for (;;) {
      std::uint64_t t = ticket_.load(std::memory_order_acquire);
      // Spin (yielding) for a while: the stages of a step follow each other
      // within microseconds. Then sleep until a new job is posted.
      const auto spinUntil = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
      while (generationOf(t) == handled) {
        if (std::chrono::steady_clock::now() < spinUntil) {
          std::this_thread::yield();
        } else {
          ticket_.wait(t, std::memory_order_acquire);
        }
        t = ticket_.load(std::memory_order_acquire);
      }
      handled = generationOf(t);
      if (id < helpers_.load(std::memory_order_relaxed)) takeChunks(handled);
    }
  }

  std::atomic<bool> busy_{false};
  std::atomic<std::uint64_t> ticket_{0};
  std::atomic<std::int64_t> remaining_{0};
  std::atomic<int> helpers_{0};
  std::uint64_t generation_ = 0;  // the caller's, under busy_
  ChunkFunction function_ = nullptr;
  void* context_ = nullptr;
  std::vector<std::thread> workers_;
};

}  // namespace

int availableThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

void runChunks(int threads, std::int64_t chunks, ChunkFunction function, void* context) {
  if (threads > 1 && chunks > 1 && Pool::instance().run(threads, chunks, function, context)) return;
  for (std::int64_t c = 0; c < chunks; ++c) function(context, c);
}

}  // namespace robophi::detail
