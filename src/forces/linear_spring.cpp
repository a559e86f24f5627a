// LS: linear spring/damper (MODEL §1).
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
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

// Spring j by the scalar kernel: the force on end a into out[j], its energy and
// power added.
inline void scalarSpring(const LinearSpring* spring, const Vec3* p, const Vec3* v, Vec3* out,
                         std::int64_t j, double& potential, double& power) {
  const LinearSpring& s = spring[j];
  Vec3 forceOnA;
  double springEnergy = 0.0, springPower = 0.0;
  if (linearSpringKernel(s, p[s.a], p[s.b], v[s.a], v[s.b], forceOnA, springEnergy, springPower)) {
    potential += springEnergy;
    power += springPower;
  }
  out[j] = forceOnA;
}

#if defined(__x86_64__) && defined(__GNUC__)
// Four springs at a time, one in each AVX lane, from `k` while four are left;
// returns where it stopped. The scalar kernel's operations in its order (no
// fused multiply-add: only AVX2 is enabled here, and -ffp-contract=off): the
// same bits. Called only when the processor has AVX2 (checked at run time).
__attribute__((target("avx2"))) std::int64_t linearSpringLanes4(const LinearSpring* spring,
                                                                const Vec3* p, const Vec3* v,
                                                                Vec3* out, std::int64_t k,
                                                                std::int64_t end, double& potential,
                                                                double& power) {
  for (; k + 3 < end; k += 4) {
    const LinearSpring &s0 = spring[k], &s1 = spring[k + 1], &s2 = spring[k + 2],
                       &s3 = spring[k + 3];
    const Vec3 &a0 = p[s0.a], &a1 = p[s1.a], &a2 = p[s2.a], &a3 = p[s3.a];
    const Vec3 &b0 = p[s0.b], &b1 = p[s1.b], &b2 = p[s2.b], &b3 = p[s3.b];
    const __m256d dx =
        _mm256_sub_pd(_mm256_set_pd(a3.x, a2.x, a1.x, a0.x), _mm256_set_pd(b3.x, b2.x, b1.x, b0.x));
    const __m256d dy =
        _mm256_sub_pd(_mm256_set_pd(a3.y, a2.y, a1.y, a0.y), _mm256_set_pd(b3.y, b2.y, b1.y, b0.y));
    const __m256d dz =
        _mm256_sub_pd(_mm256_set_pd(a3.z, a2.z, a1.z, a0.z), _mm256_set_pd(b3.z, b2.z, b1.z, b0.z));
    const __m256d length = _mm256_sqrt_pd(_mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz)));
    if (_mm256_movemask_pd(_mm256_cmp_pd(length, _mm256_setzero_pd(), _CMP_GT_OQ)) != 15) {
      // Coincident particles in a lane: the scalar kernel takes the four.
      for (std::int64_t j = k; j < k + 4; ++j) scalarSpring(spring, p, v, out, j, potential, power);
      continue;
    }
    const __m256d inverse = _mm256_div_pd(_mm256_set1_pd(1.0), length);
    const __m256d kx = _mm256_mul_pd(dx, inverse), ky = _mm256_mul_pd(dy, inverse),
                  kz = _mm256_mul_pd(dz, inverse);
    const __m256d stretch = _mm256_sub_pd(
        length, _mm256_set_pd(s3.restLength, s2.restLength, s1.restLength, s0.restLength));
    const Vec3 &va0 = v[s0.a], &va1 = v[s1.a], &va2 = v[s2.a], &va3 = v[s3.a];
    const Vec3 &vb0 = v[s0.b], &vb1 = v[s1.b], &vb2 = v[s2.b], &vb3 = v[s3.b];
    const __m256d ux = _mm256_sub_pd(_mm256_set_pd(va3.x, va2.x, va1.x, va0.x),
                                     _mm256_set_pd(vb3.x, vb2.x, vb1.x, vb0.x));
    const __m256d uy = _mm256_sub_pd(_mm256_set_pd(va3.y, va2.y, va1.y, va0.y),
                                     _mm256_set_pd(vb3.y, vb2.y, vb1.y, vb0.y));
    const __m256d uz = _mm256_sub_pd(_mm256_set_pd(va3.z, va2.z, va1.z, va0.z),
                                     _mm256_set_pd(vb3.z, vb2.z, vb1.z, vb0.z));
    const __m256d stretchRate = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(ux, kx), _mm256_mul_pd(uy, ky)), _mm256_mul_pd(uz, kz));
    const __m256d stiffness = _mm256_set_pd(s3.stiffness, s2.stiffness, s1.stiffness, s0.stiffness);
    const __m256d dampingForce =
        _mm256_mul_pd(_mm256_set_pd(s3.damping, s2.damping, s1.damping, s0.damping), stretchRate);
    const __m256d magnitude = _mm256_sub_pd(
        _mm256_mul_pd(_mm256_set_pd(-s3.stiffness, -s2.stiffness, -s1.stiffness, -s0.stiffness),
                      stretch),
        dampingForce);
    const __m256d fx = _mm256_mul_pd(kx, magnitude), fy = _mm256_mul_pd(ky, magnitude),
                  fz = _mm256_mul_pd(kz, magnitude);
    const __m256d energy = _mm256_mul_pd(
        _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0.5), stiffness), stretch), stretch);
    const __m256d springPower =
        _mm256_mul_pd(_mm256_xor_pd(dampingForce, _mm256_set1_pd(-0.0)), stretchRate);
    alignas(32) double e[4], w[4], x[4], y[4], z[4];
    _mm256_store_pd(e, energy);
    _mm256_store_pd(w, springPower);
    _mm256_store_pd(x, fx);
    _mm256_store_pd(y, fy);
    _mm256_store_pd(z, fz);
    for (int i = 0; i < 4; ++i) out[k + i] = {x[i], y[i], z[i]};
    for (int i = 0; i < 4; ++i) potential += e[i];
    for (int i = 0; i < 4; ++i) power += w[i];
  }
  return k;
}
const bool kHaveAvx2 = [] {
  __builtin_cpu_init();  // (a static initialiser may run before libgcc's)
  return __builtin_cpu_supports("avx2") != 0;
}();
#endif

// Springs [begin, end): the force on end a into out[k], energy and power added to
// `potential` and `power` in ascending k.
void linearSpringRange(const LinearSpring* spring, const Vec3* p, const Vec3* v, Vec3* out,
                       std::int64_t begin, std::int64_t end, double& potential, double& power) {
  // One spring by the scalar kernel.
  auto single = [&](std::int64_t j) { scalarSpring(spring, p, v, out, j, potential, power); };
  std::int64_t k = begin;
#if defined(__x86_64__) && defined(__GNUC__)
  if (kHaveAvx2) k = linearSpringLanes4(spring, p, v, out, k, end, potential, power);
#endif
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

// The serial scatter `sum[a] += F; sum[b] -= F` over springs [0, count), in
// spring order, of the ends whose bit in dependent[k] (bit 0: a, bit 1: b) is
// `want` (null `dependent`: every end, want 0). The particle last reached by an
// end a stays in a register while the next springs' ends reach it (a cloth's
// springs share their end a by threes): the same additions in the same order.
inline void scatterSprings(const LinearSpring* spring, const std::uint8_t* dependent,
                           const Vec3* onA, std::int64_t count, bool want, Vec3* sum) {
  ParticleIndex current = -1;
  Vec3 held{};
  for (std::int64_t k = 0; k < count; ++k) {
    const std::uint8_t d = dependent != nullptr ? dependent[k] : 0;
    const Vec3 f = onA[k];
    if (((d & 1) != 0) == want) {
      const ParticleIndex a = spring[k].a;
      if (a != current) {
        if (current >= 0) sum[current] = held;
        current = a;
        held = sum[a];
      }
      held += f;
    }
    if (((d & 2) != 0) == want) {
      const ParticleIndex b = spring[k].b;
      if (b == current) {
        held -= f;
      } else {
        sum[b] -= f;
      }
    }
  }
  if (current >= 0) sum[current] = held;
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
  // The parallel job's dependences: an end is dependent when its particle has a
  // spring in an earlier chunk (its first entry is its lowest spring).
  const std::int64_t chunk = detail::kParallelChunk;
  const std::size_t springCount = model.linearSprings.size();
  const auto springChunks = static_cast<std::int64_t>((springCount + chunk - 1) / chunk);
  incidence.dependent.assign(springCount, 0);
  incidence.waitFrom.resize(static_cast<std::size_t>(springChunks));
  auto firstChunk = [&](ParticleIndex p) {
    return (incidence
                .entry[static_cast<std::size_t>(incidence.start[static_cast<std::size_t>(p)])] >>
            1) /
           chunk;
  };
  for (std::int64_t c = 0; c < springChunks; ++c) {
    std::int64_t from = c;
    for (std::size_t k = static_cast<std::size_t>(c * chunk);
         k < std::min(springCount, static_cast<std::size_t>((c + 1) * chunk)); ++k) {
      const LinearSpring& s = model.linearSprings[k];
      const std::int64_t fa = firstChunk(s.a), fb = firstChunk(s.b);
      if (fa < c) incidence.dependent[k] |= 1;
      if (fb < c) incidence.dependent[k] |= 2;
      from = std::min(from, std::min(fa, fb));
    }
    incidence.waitFrom[static_cast<std::size_t>(c)] = static_cast<std::int32_t>(from);
  }
  // With a prologue: each particle chunk one spring chunk ahead of the first that reads it.
  const auto particleChunks = static_cast<std::int64_t>((n + chunk - 1) / chunk);
  incidence.reads.assign(static_cast<std::size_t>(springChunks), {0, -1});
  incidence.order.clear();
  incidence.order.reserve(static_cast<std::size_t>(springChunks + particleChunks));
  std::int64_t emitted = 0;  // particle chunks [0, emitted) are in the order
  for (std::int64_t c = 0; c < springChunks; ++c) {
    std::int64_t low = particleChunks, high = -1;
    for (std::size_t k = static_cast<std::size_t>(c * chunk);
         k < std::min(springCount, static_cast<std::size_t>((c + 1) * chunk)); ++k) {
      const LinearSpring& s = model.linearSprings[k];
      low = std::min(low, static_cast<std::int64_t>(std::min(s.a, s.b)) / chunk);
      high = std::max(high, static_cast<std::int64_t>(std::max(s.a, s.b)) / chunk);
    }
    if (high >= 0)
      incidence.reads[static_cast<std::size_t>(c)] = {static_cast<std::int32_t>(low),
                                                      static_cast<std::int32_t>(high)};
    for (; emitted < std::min(particleChunks, high + 2); ++emitted)
      incidence.order.push_back(static_cast<std::int32_t>(-1 - emitted));
    incidence.order.push_back(static_cast<std::int32_t>(c));
  }
  for (; emitted < particleChunks; ++emitted)
    incidence.order.push_back(static_cast<std::int32_t>(-1 - emitted));
  return incidence;
}

ForceTally accumulateLinearSprings(const Model& model, const SpringIncidence& incidence,
                                   int threads, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                   ForceScratch& scratch, const ParticlePrologue* prologue) {
  const std::vector<LinearSpring>& springs = model.linearSprings;
  const auto springCount = static_cast<std::int64_t>(springs.size());
  std::vector<Vec3>& springForce = scratch.springForce;
  const std::size_t chunk = static_cast<std::size_t>(detail::kParallelChunk);
  const bool tableFits =
      incidence.start.size() == position.size() + 1 &&
      incidence.entry.size() == 2 * springs.size() &&
      incidence.dependent.size() == springs.size() &&
      incidence.waitFrom.size() == (springs.size() + chunk - 1) / chunk &&
      incidence.reads.size() == incidence.waitFrom.size() &&
      incidence.order.size() == incidence.reads.size() + (position.size() + chunk - 1) / chunk;
  if (threads <= 1 || springCount < detail::kParallelMinimum || !tableFits) {
    if (prologue != nullptr) {  // first, as a parallel loop of its own
      const auto particles = static_cast<std::int64_t>(position.size());
      detail::runChunks(particles >= detail::kParallelMinimum ? threads : 1,
                        (particles + detail::kParallelChunk - 1) / detail::kParallelChunk,
                        prologue->run, prologue->context);
    }
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
      scatterSprings(springs.data() + begin, nullptr, springForce.data(), end - begin, false,
                     force.data());
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
  // One job (core/parallel.h) of spring chunks, each as the one-thread loop above:
  // its forces into a buffer of the thread's, then the scatter `force[a] += F;
  // force[b] -= F` in spring order to its particles that have no spring in an
  // earlier chunk (incidence.dependent). The other ends' forces wait in
  // springForce; their scatters run in chunk order, each once its chunk and all
  // before it are ready, on whichever thread finds them so (a try-lock: no thread
  // waits for another). Each particle gets its springs' forces in ascending
  // order, as from the serial scatter: the same bits.
  springForce.resize(springs.size());
  const auto springChunks =
      static_cast<std::size_t>((springCount + detail::kParallelChunk - 1) / detail::kParallelChunk);
  const std::size_t particleChunks = incidence.order.size() - springChunks;
  if (scratch.springChunkDone.size() != springChunks ||
      scratch.particleChunkDone.size() != particleChunks) {
    // Both anew (their stamps zero), as the job count restarts.
    scratch.springChunkDone = std::vector<std::atomic<std::uint32_t>>(springChunks);
    scratch.particleChunkDone = std::vector<std::atomic<std::uint32_t>>(particleChunks);
    for (auto& d : scratch.springChunkDone) d.store(0, std::memory_order_relaxed);
    for (auto& d : scratch.particleChunkDone) d.store(0, std::memory_order_relaxed);
    scratch.springJob = 0;
  }
  scratch.springChunkSums.resize(springChunks);
  if (++scratch.springJob == 0) {  // the stamps wrap: clear them
    for (auto& d : scratch.springChunkDone) d.store(0, std::memory_order_relaxed);
    for (auto& d : scratch.particleChunkDone) d.store(0, std::memory_order_relaxed);
    scratch.springJob = 1;
  }
  struct Context {
    const LinearSpring* springs;
    std::int64_t springCount, chunks;
    const Vec3 *position, *velocity;
    Vec3* sum;
    Vec3* held;
    const std::uint8_t* dependent;
    const std::int32_t* waitFrom;
    std::array<double, 2>* sums;
    std::atomic<std::uint32_t>* ready;
    std::uint32_t job;
    const ParticlePrologue* prologue;
    const std::int32_t* order;
    const std::array<std::int32_t, 2>* reads;
    std::atomic<std::uint32_t>* prologueDone;
    std::atomic<bool> combining{false};
    std::atomic<std::int64_t> scattered{0};  // chunks whose dependent ends are scattered
  } context{springs.data(),
            springCount,
            static_cast<std::int64_t>(springChunks),
            position.data(),
            velocity.data(),
            force.data(),
            springForce.data(),
            incidence.dependent.data(),
            incidence.waitFrom.data(),
            scratch.springChunkSums.data(),
            scratch.springChunkDone.data(),
            scratch.springJob,
            prologue,
            incidence.order.data(),
            incidence.reads.data(),
            scratch.particleChunkDone.data()};
  detail::runChunks(
      threads,
      static_cast<std::int64_t>(prologue != nullptr ? incidence.order.size() : springChunks),
      [](void* raw, std::int64_t item) {
        Context& x = *static_cast<Context*>(raw);
        std::int64_t c = item;
        if (x.prologue != nullptr) {
          c = x.order[item];
          if (c < 0) {  // a chunk of the particle pass
            x.prologue->run(x.prologue->context, -1 - c);
            x.prologueDone[-1 - c].store(x.job, std::memory_order_release);
            return;
          }
          // Taken before this chunk: done, or in progress on another thread.
          for (std::int32_t g = x.reads[c][0]; g <= x.reads[c][1]; ++g) {
            while (x.prologueDone[g].load(std::memory_order_acquire) != x.job)
              std::this_thread::yield();
          }
        }
        alignas(64) thread_local Vec3 onA[detail::kParallelChunk];
        const std::int64_t begin = c * detail::kParallelChunk;
        const std::int64_t end = std::min(x.springCount, begin + detail::kParallelChunk);
        double potential = 0.0, power = 0.0;
        const LinearSpring* spring = x.springs + begin;
        const std::uint8_t* dependent = x.dependent + begin;
        const std::int64_t count = end - begin;
        linearSpringRange(spring, x.position, x.velocity, onA, 0, count, potential, power);
        x.sums[c] = {potential, power};
        Vec3* sum = x.sum;
        Vec3* held = x.held + begin;
        scatterSprings(spring, dependent, onA, count, false, sum);
        for (std::int64_t k = 0; k < count; ++k) {
          if (dependent[k] != 0) held[k] = onA[k];
        }
        // Sequentially consistent: a thread that fails to take the lock has made
        // its chunk ready before, and the holder looks again after letting go.
        x.ready[c].store(x.job);
        for (;;) {
          if (x.combining.exchange(true)) return;  // the holder scatters it
          std::int64_t next = x.scattered.load(std::memory_order_relaxed);
          while (next < x.chunks && x.ready[next].load() == x.job) {
            if (x.waitFrom[next] < next) {  // it has dependent ends
              const std::int64_t from = next * detail::kParallelChunk;
              const std::int64_t to = std::min(x.springCount, from + detail::kParallelChunk);
              scatterSprings(x.springs + from, x.dependent + from, x.held + from, to - from, true,
                             sum);
            }
            ++next;
          }
          x.scattered.store(next, std::memory_order_relaxed);
          x.combining.store(false);
          if (!(next < x.chunks && x.ready[next].load() == x.job)) return;
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
