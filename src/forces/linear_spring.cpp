// LS: linear spring/damper (MODEL §1).
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
  return incidence;
}

ForceTally accumulateLinearSprings(const Model& model, const SpringIncidence& incidence,
                                   int threads, const std::vector<Vec3>& position,
                                   const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                                   ForceScratch& scratch) {
  const std::vector<LinearSpring>& springs = model.linearSprings;
  const auto springCount = static_cast<std::int64_t>(springs.size());
  std::vector<Vec3>& springForce = scratch.springForce;
  const bool tableFits =
      incidence.start.size() == position.size() + 1 && incidence.entry.size() == 2 * springs.size();
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
  // Pass 1: per spring; potential and power summed in fixed chunks (core/parallel.h).
  const std::array<double, 2> sums = detail::parallelSum<2>(
      threads, springCount, {0.0, 0.0},
      [&](std::int64_t begin, std::int64_t end, std::array<double, 2>& tally) {
        // Local sums: the stores to springForce cannot alias them.
        double potential = tally[0], power = tally[1];
        linearSpringRange(springs.data(), position.data(), velocity.data(), springForce.data(),
                          begin, end, potential, power);
        tally = {potential, power};
      });
  // Pass 2: each particle adds its springs in ascending order, as the serial
  // scatter `force[a] += F; force[b] -= F` does.
  {
    const std::int32_t* start = incidence.start.data();
    const std::int32_t* entry = incidence.entry.data();
    const Vec3* onA = springForce.data();
    Vec3* sum = force.data();
    detail::parallelFor(threads, static_cast<std::int64_t>(position.size()),
                        [&](std::int64_t begin, std::int64_t end) {
                          for (std::int64_t i = begin; i < end; ++i) {
                            Vec3 f = sum[i];
                            for (std::int32_t e = start[i]; e < start[i + 1]; ++e) {
                              const std::int32_t code = entry[e];
                              if ((code & 1) == 0) {
                                f += onA[code >> 1];
                              } else {
                                f -= onA[code >> 1];
                              }
                            }
                            sum[i] = f;
                          }
                        });
  }
  ForceTally tally;
  tally.potential = sums[0];
  tally.dissipativePower = sums[1];
  return tally;
}

}  // namespace robophi
