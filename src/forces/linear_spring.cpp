// LS: linear spring/damper (MODEL §1).
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <thread>

#include "core/parallel.h"
#include "forces/forces.h"
#include "robophi/connector_forces.h"

namespace robophi {

namespace {

// MODEL §1 LS: l = |p_a - p_b|, k̂ = (p_a - p_b)/l, Δl = l - l0, l̇ = (v_a - v_b)·k̂,
// F_a = (-κ Δl - μ l̇) k̂. Returns false (and no force) for coincident particles.
inline bool linearSpringKernel(const LinearSpring& s, const Vec3& pA, const Vec3& pB,
                               const Vec3& vA, const Vec3& vB, Vec3& forceOnA, double& energy,
                               double& power) {
  const Vec3 delta = pA - pB;
  const double length = norm(delta);
  if (!(length > 0.0)) return false;
  const Vec3 kHat = delta * (1.0 / length);
  const double stretch = length - s.restLength;
  const double stretchRate = dot(vA - vB, kHat);
  const double dampingForce = s.damping * stretchRate;
  forceOnA = kHat * (-s.stiffness * stretch - dampingForce);
  energy = 0.5 * s.stiffness * stretch * stretch;
  power = -dampingForce * stretchRate;
  return true;
}

// Springs [begin, end): the force on end a into out[k], energy and power added to
// `potential` and `power` in ascending k.
void linearSpringRange(const LinearSpring* spring, const Vec3* p, const Vec3* v, Vec3* out,
                       std::int64_t begin, std::int64_t end, double& potential, double& power) {
  // One spring by the scalar kernel.
  auto single = [&](std::int64_t j) {
    const LinearSpring& s = spring[j];
    Vec3 forceOnA;
    double springEnergy = 0.0, springPower = 0.0;
    if (linearSpringKernel(s, p[s.a], p[s.b], v[s.a], v[s.b], forceOnA, springEnergy,
                           springPower)) {
      potential += springEnergy;
      power += springPower;
    }
    out[j] = forceOnA;
  };
  std::int64_t k = begin;
#if defined(__SSE2__)
  // Two springs at a time, one in each lane: the kernel's operations in its order
  // (IEEE sqrt and division are exact-rounded in both forms), so the same bits.
  for (; k + 1 < end; k += 2) {
    const LinearSpring& s0 = spring[k];
    const LinearSpring& s1 = spring[k + 1];
    const Vec3 &a0 = p[s0.a], &b0 = p[s0.b], &a1 = p[s1.a], &b1 = p[s1.b];
    const __m128d dx = _mm_sub_pd(_mm_set_pd(a1.x, a0.x), _mm_set_pd(b1.x, b0.x));
    const __m128d dy = _mm_sub_pd(_mm_set_pd(a1.y, a0.y), _mm_set_pd(b1.y, b0.y));
    const __m128d dz = _mm_sub_pd(_mm_set_pd(a1.z, a0.z), _mm_set_pd(b1.z, b0.z));
    const __m128d length = _mm_sqrt_pd(
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz)));
    // Coincident particles in either lane: the scalar kernel takes both.
    if (_mm_movemask_pd(_mm_cmpgt_pd(length, _mm_setzero_pd())) != 3) {
      single(k);
      single(k + 1);
      continue;
    }
    const __m128d inverse = _mm_div_pd(_mm_set1_pd(1.0), length);
    const __m128d kx = _mm_mul_pd(dx, inverse), ky = _mm_mul_pd(dy, inverse),
                  kz = _mm_mul_pd(dz, inverse);
    const __m128d stretch = _mm_sub_pd(length, _mm_set_pd(s1.restLength, s0.restLength));
    const Vec3 &va0 = v[s0.a], &vb0 = v[s0.b], &va1 = v[s1.a], &vb1 = v[s1.b];
    const __m128d ux = _mm_sub_pd(_mm_set_pd(va1.x, va0.x), _mm_set_pd(vb1.x, vb0.x));
    const __m128d uy = _mm_sub_pd(_mm_set_pd(va1.y, va0.y), _mm_set_pd(vb1.y, vb0.y));
    const __m128d uz = _mm_sub_pd(_mm_set_pd(va1.z, va0.z), _mm_set_pd(vb1.z, vb0.z));
    const __m128d stretchRate =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(ux, kx), _mm_mul_pd(uy, ky)), _mm_mul_pd(uz, kz));
    const __m128d stiffness = _mm_set_pd(s1.stiffness, s0.stiffness);
    const __m128d dampingForce = _mm_mul_pd(_mm_set_pd(s1.damping, s0.damping), stretchRate);
    const __m128d magnitude =
        _mm_sub_pd(_mm_mul_pd(_mm_set_pd(-s1.stiffness, -s0.stiffness), stretch), dampingForce);
    const __m128d fx = _mm_mul_pd(kx, magnitude), fy = _mm_mul_pd(ky, magnitude),
                  fz = _mm_mul_pd(kz, magnitude);
    const __m128d energy =
        _mm_mul_pd(_mm_mul_pd(_mm_mul_pd(_mm_set1_pd(0.5), stiffness), stretch), stretch);
    const __m128d springPower =
        _mm_mul_pd(_mm_xor_pd(dampingForce, _mm_set1_pd(-0.0)), stretchRate);
    alignas(16) double e[2], w[2], x[2], y[2], z[2];
    _mm_store_pd(e, energy);
    _mm_store_pd(w, springPower);
    _mm_store_pd(x, fx);
    _mm_store_pd(y, fy);
    _mm_store_pd(z, fz);
    out[k] = {x[0], y[0], z[0]};
    out[k + 1] = {x[1], y[1], z[1]};
    potential += e[0];
    potential += e[1];
    power += w[0];
    power += w[1];
  }
#endif
  for (; k < end; ++k) single(k);
}

}  // namespace

LinearSpringForce linearSpringForce(const LinearSpring& spring, const Vec3& pA, const Vec3& pB,
                                    const Vec3& vA, const Vec3& vB) {
  LinearSpringForce result;
  if (linearSpringKernel(spring, pA, pB, vA, vB, result.onA, result.energy,
                         result.dissipativePower)) {
    result.onB = -result.onA;
  }
  return result;
}

SpringIncidence compileSpringIncidence(const Model& model) {
  SpringIncidence incidence;
  const auto n = static_cast<std::size_t>(model.particleCount());
  incidence.start.assign(n + 1, 0);
  for (const LinearSpring& s : model.linearSprings) {
    ++incidence.start[static_cast<std::size_t>(s.a) + 1];
    ++incidence.start[static_cast<std::size_t>(s.b) + 1];
  }
  for (std::size_t i = 0; i < n; ++i) incidence.start[i + 1] += incidence.start[i];
  incidence.entry.resize(2 * model.linearSprings.size());
  std::vector<std::int32_t> next(incidence.start.begin(), incidence.start.end() - 1);
  // Springs in ascending order, so each particle's entries are ascending.
  for (std::size_t k = 0; k < model.linearSprings.size(); ++k) {
    const LinearSpring& s = model.linearSprings[k];
    const auto end = static_cast<std::int32_t>(2 * k);
    incidence.entry[static_cast<std::size_t>(next[static_cast<std::size_t>(s.a)]++)] = end;
    incidence.entry[static_cast<std::size_t>(next[static_cast<std::size_t>(s.b)]++)] = end + 1;
  }
  // The parallel job's order: each particle chunk's gather two spring chunks
  // after the last one it reads, so that those are done (or nearly) when it is
  // taken, and the forces it reads are still in a cache.
  constexpr std::int64_t kLag = 2;
  const std::int64_t chunk = detail::kParallelChunk;
  const auto springChunks =
      static_cast<std::int64_t>((model.linearSprings.size() + chunk - 1) / chunk);
  const auto particleChunks = static_cast<std::int64_t>((n + chunk - 1) / chunk);
  incidence.reads.assign(static_cast<std::size_t>(particleChunks), {0, -1});
  std::vector<std::vector<std::int32_t>> after(static_cast<std::size_t>(springChunks) + 1);
  for (std::int64_t g = 0; g < particleChunks; ++g) {
    std::int32_t first = -1, last = -1;
    const std::size_t begin = static_cast<std::size_t>(g * chunk);
    const std::size_t end = std::min(n, begin + static_cast<std::size_t>(chunk));
    for (std::int32_t e = incidence.start[begin]; e < incidence.start[end]; ++e) {
      const auto c = static_cast<std::int32_t>((incidence.entry[static_cast<std::size_t>(e)] >> 1) / chunk);
      if (first < 0 || c < first) first = c;
      if (c > last) last = c;
    }
    if (last >= 0) incidence.reads[static_cast<std::size_t>(g)] = {first, last};
    // Gathers that read nothing first (slot 0), the others after spring chunk last + kLag.
    const std::int64_t slot = last < 0 ? 0 : std::min(springChunks, last + kLag + 1);
    after[static_cast<std::size_t>(slot)].push_back(static_cast<std::int32_t>(-1 - g));
  }
  incidence.order.reserve(static_cast<std::size_t>(springChunks + particleChunks));
  for (std::int64_t s = 0; s <= springChunks; ++s) {
    for (std::int32_t item : after[static_cast<std::size_t>(s)]) incidence.order.push_back(item);
    if (s < springChunks) incidence.order.push_back(static_cast<std::int32_t>(s));
  }
  return incidence;
}

ForceTally accumulateLinearSprings(const Model& model, const SpringIncidence& incidence,
                                   int threads, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                   ForceScratch& scratch) {
  const std::vector<LinearSpring>& springs = model.linearSprings;
  const auto springCount = static_cast<std::int64_t>(springs.size());
  std::vector<Vec3>& springForce = scratch.springForce;
  const std::size_t chunk = static_cast<std::size_t>(detail::kParallelChunk);
  const bool tableFits =
      incidence.start.size() == position.size() + 1 &&
      incidence.entry.size() == 2 * springs.size() &&
      incidence.reads.size() == (position.size() + chunk - 1) / chunk &&
      incidence.order.size() == incidence.reads.size() + (springs.size() + chunk - 1) / chunk;
  if (threads <= 1 || springCount < detail::kParallelMinimum || !tableFits) {
    // One thread: each chunk's forces into a buffer that stays in cache, then the
    // serial scatter `force[a] += F; force[b] -= F` in spring order, which is what
    // the gather below adds for each particle (ascending springs); the sums are
    // taken in the same chunks. The same bits as the two passes, in one.
    springForce.resize(std::min<std::size_t>(springs.size(), detail::kParallelChunk));
    double potential = 0.0, power = 0.0;
    for (std::int64_t begin = 0; begin < springCount; begin += detail::kParallelChunk) {
      const std::int64_t end = std::min(springCount, begin + detail::kParallelChunk);
      double chunkPotential = 0.0, chunkPower = 0.0;
      linearSpringRange(springs.data() + begin, position.data(), velocity.data(),
                        springForce.data(), 0, end - begin, chunkPotential, chunkPower);
      for (std::int64_t k = begin; k < end; ++k) {
        const Vec3& onA = springForce[static_cast<std::size_t>(k - begin)];
        force[springs[static_cast<std::size_t>(k)].a] += onA;
        force[springs[static_cast<std::size_t>(k)].b] -= onA;
      }
      if (begin == 0) {
        potential = chunkPotential;
        power = chunkPower;
      } else {
        potential += chunkPotential;
        power += chunkPower;
      }
    }
    ForceTally tally;
    tally.potential = potential;
    tally.dissipativePower = power;
    return tally;
  }
  springForce.resize(springs.size());
  // One job (core/parallel.h): the spring chunks, each spring's force on its end
  // a into springForce, potential and power summed per chunk; and the gathers by
  // particle chunk, each adding its particles' springs in ascending order (as the
  // serial scatter `force[a] += F; force[b] -= F` does) once the spring chunks it
  // reads are done (incidence.order places it after them).
  const auto springChunks =
      static_cast<std::size_t>((springCount + detail::kParallelChunk - 1) / detail::kParallelChunk);
  if (scratch.springChunkDone.size() != springChunks) {
    scratch.springChunkDone = std::vector<std::atomic<std::uint32_t>>(springChunks);
    scratch.springJob = 0;
  }
  scratch.springChunkSums.resize(springChunks);
  if (++scratch.springJob == 0) {  // the stamps wrap: clear them
    for (auto& d : scratch.springChunkDone) d.store(0, std::memory_order_relaxed);
    scratch.springJob = 1;
  }
  struct Context {
    const LinearSpring* springs;
    std::int64_t springCount, particleCount;
    const Vec3 *position, *velocity;
    Vec3* onA;
    Vec3* sum;
    const std::int32_t *start, *entry, *order;
    const std::array<std::int32_t, 2>* reads;
    std::array<double, 2>* sums;
    std::atomic<std::uint32_t>* done;
    std::uint32_t job;
  } context{springs.data(),
            springCount,
            static_cast<std::int64_t>(position.size()),
            position.data(),
            velocity.data(),
            springForce.data(),
            force.data(),
            incidence.start.data(),
            incidence.entry.data(),
            incidence.order.data(),
            incidence.reads.data(),
            scratch.springChunkSums.data(),
            scratch.springChunkDone.data(),
            scratch.springJob};
  detail::runChunks(
      threads, static_cast<std::int64_t>(incidence.order.size()),
      [](void* raw, std::int64_t item) {
        const Context& x = *static_cast<const Context*>(raw);
        const std::int32_t code = x.order[item];
        if (code >= 0) {
          const std::int64_t begin = code * detail::kParallelChunk;
          const std::int64_t end = std::min(x.springCount, begin + detail::kParallelChunk);
          double potential = 0.0, power = 0.0;
          linearSpringRange(x.springs, x.position, x.velocity, x.onA, begin, end, potential,
                            power);
          x.sums[code] = {potential, power};
          x.done[code].store(x.job, std::memory_order_release);
          return;
        }
        const std::int64_t g = -1 - static_cast<std::int64_t>(code);
        const std::array<std::int32_t, 2> reads = x.reads[g];
        for (std::int32_t c = reads[0]; c <= reads[1]; ++c) {
          // A chunk taken before this one, in progress on another thread.
          while (x.done[c].load(std::memory_order_acquire) != x.job) std::this_thread::yield();
        }
        const std::int64_t end = std::min(x.particleCount, (g + 1) * detail::kParallelChunk);
        for (std::int64_t i = g * detail::kParallelChunk; i < end; ++i) {
          Vec3 f = x.sum[i];
          for (std::int32_t e = x.start[i]; e < x.start[i + 1]; ++e) {
            const std::int32_t spring = x.entry[e];
            if ((spring & 1) == 0) {
              f += x.onA[spring >> 1];
            } else {
              f -= x.onA[spring >> 1];
            }
          }
          x.sum[i] = f;
        }
      },
      &context);
  // The chunks' sums in chunk order (core/parallel.h's parallelSum).
  std::array<double, 2> sums = scratch.springChunkSums[0];
  for (std::size_t c = 1; c < springChunks; ++c) {
    sums[0] += scratch.springChunkSums[c][0];
    sums[1] += scratch.springChunkSums[c][1];
  }
  ForceTally tally;
  tally.potential = sums[0];
  tally.dissipativePower = sums[1];
  return tally;
}

}  // namespace robophi
