// The energy-based adaptive time step (MODEL §4, docs/adaptive-step.md).
#include "robophi/adaptive_step.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "core/text.h"
#include "integrate/object_box.h"
#include "robophi/connector_forces.h"

namespace robophi {

Vec3 sceneFrameVelocity(const Model& model, const State& state) {
  // MODEL §4.1: the frame the scene's physics is at rest in. Fixed particles
  // (a base, a palm, a kinematic robot) carry it when there are any.
  // (Called at every trial step: the free particles are summed only when no
  // particle is fixed.)
  Vec3 fixedMomentum;
  double fixedMass = 0.0;
  std::int64_t fixedCount = 0;
  Vec3 fixedSum;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (model.moves(i)) continue;  // (a rigid tree's particles move with their body)
    fixedMomentum += state.velocity[i] * model.mass[i];
    fixedMass += model.mass[i];
    fixedSum += state.velocity[i];
    ++fixedCount;
  }
  if (fixedCount > 0)
    return fixedMass > 0.0 ? fixedMomentum / fixedMass : fixedSum / static_cast<double>(fixedCount);
  Vec3 freeMomentum;
  double freeMass = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    freeMomentum += state.velocity[i] * model.mass[i];
    freeMass += model.mass[i];
  }
  const Environment& env = model.environment;
  // Anything but planes (and a medium at rest, or a particle's drag −c v, which
  // acts against the world's frame) fixes the frame to the world's.
  const bool drag = std::any_of(model.linearDamping.begin(), model.linearDamping.end(),
                                [](double c) { return c > 0.0; });
  if (!env.heightfields.empty() || !env.boxes.empty() || !env.spheres.empty() ||
      env.viscosity > 0.0 || drag || !(freeMass > 0.0))
    return {};
  // Planes leave the motion along them free: project the centre-of-mass
  // velocity onto the common tangent space (Gram-Schmidt on the normals).
  Vec3 v = freeMomentum / freeMass;
  std::vector<Vec3> basis;
  for (const GroundPlane& plane : env.planes) {
    Vec3 n = plane.normal;
    for (const Vec3& b : basis) n -= b * dot(n, b);
    const double length = norm(n);
    if (length > 1e-9) basis.push_back(n / length);
  }
  for (const Vec3& b : basis) v -= b * dot(v, b);
  return v;
}

double activeEnergy(const Model& model, const State& state, const EnergyTally& energy) {
  // MODEL §4.1: kinetic energy in the scene's frame plus the elastic
  // potentials (gravity's potential depends on the datum and sets no scale).
  const Vec3 frame = sceneFrameVelocity(model, state);
  double kinetic = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    if (model.moves(i)) kinetic += 0.5 * model.mass[i] * squaredNorm(state.velocity[i] - frame);
  }
  return kinetic + energy.linearSpring + energy.torsionSpring + energy.jointSpring + energy.contact;
}

double gravityEnergyScale(const Model& model, const State& state) {
  // Σ m_i |g| × L: L the diagonal of the box around the particles, or the
  // largest height of a particle above a plane that faces against gravity
  // (a single ball above the ground has no box), or the largest free particle's
  // diameter (a single ball on a heightfield, a box or a sphere has neither),
  // whichever is larger.
  if (state.position.empty()) return 0.0;
  const double g = norm(model.gravity);
  if (!(g > 0.0)) return 0.0;
  Vec3 low = state.position.front(), high = low;
  double freeMass = 0.0, height = 0.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const Vec3& p = state.position[i];
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
    if (!model.moves(i)) continue;
    freeMass += model.mass[i];
    height = std::max(height, 2.0 * model.radius[i]);
    for (const GroundPlane& plane : model.environment.planes) {
      if (dot(plane.normal, model.gravity) < 0.0)
        height = std::max(height, dot(p - plane.point, plane.normal));
    }
  }
  return freeMass * g * std::max(norm(high - low), height);
}

double energyRoundoffScale(const EnergyTally& e) {
  const double magnitude = std::abs(e.kinetic) + std::abs(e.linearSpring) +
                           std::abs(e.torsionSpring) + std::abs(e.jointSpring) +
                           std::abs(e.gravity) + std::abs(e.contact) + std::abs(e.dissipated) +
                           std::abs(e.external);
  return 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

double energyAccountScale(const Model& model, const State& state, const EnergyTally& energy) {
  return std::max({activeEnergy(model, state, energy), gravityEnergyScale(model, state),
                   1.0e6 * energyRoundoffScale(energy)});
}

namespace {

// The largest δ with w δ + ½ a δ² ≤ D: 2D / (w + √(w² + 2aD)).
double closingStep(double w, double a, double distance) {
  if (!(distance > 0.0)) return 0.0;
  const double denominator = w + std::sqrt(w * w + 2.0 * a * distance);
  return denominator > 0.0 ? 2.0 * distance / denominator : std::numeric_limits<double>::infinity();
}

// An object's particles, bounded: the sphere around them, the centres of the
// boxes around their velocities and accelerations and the largest deviation
// from those centres, and the smallest radius.
struct ObjectBounds {
  Vec3 centre, velocity, acceleration;
  double radius = 0.0, velocitySpread = 0.0, accelerationSpread = 0.0;
  double smallestRadius = std::numeric_limits<double>::infinity();
  bool empty = true;
};

// The objects against each other (MODEL §4.4): many (a pile) without the gaps,
// through the spread of all of them (linear); few pair by pair, with the gaps.
// An empty object (a virtual one: it touches nothing) is left out.
double objectPairsStep(const std::vector<ObjectBounds>& bounds, double fraction) {
  double step = std::numeric_limits<double>::infinity();
  constexpr std::size_t kPairwiseObjects = 128;
  if (bounds.size() > kPairwiseObjects) {
    Vec3 low = bounds[0].velocity, high = low, aLowAll = bounds[0].acceleration, aHighAll = aLowAll;
    double smallest = std::numeric_limits<double>::infinity();
    for (const ObjectBounds& b : bounds) {
      if (b.empty) continue;
      low = {std::min(low.x, b.velocity.x), std::min(low.y, b.velocity.y),
             std::min(low.z, b.velocity.z)};
      high = {std::max(high.x, b.velocity.x), std::max(high.y, b.velocity.y),
              std::max(high.z, b.velocity.z)};
      aLowAll = {std::min(aLowAll.x, b.acceleration.x), std::min(aLowAll.y, b.acceleration.y),
                 std::min(aLowAll.z, b.acceleration.z)};
      aHighAll = {std::max(aHighAll.x, b.acceleration.x), std::max(aHighAll.y, b.acceleration.y),
                  std::max(aHighAll.z, b.acceleration.z)};
      smallest = std::min(smallest, b.smallestRadius);
    }
    const Vec3 vc = (low + high) * 0.5, ac = (aLowAll + aHighAll) * 0.5;
    double w = 0.0, acc = 0.0;
    for (const ObjectBounds& b : bounds) {
      if (b.empty) continue;
      w = std::max(w, norm(b.velocity - vc) + b.velocitySpread);
      acc = std::max(acc, norm(b.acceleration - ac) + b.accelerationSpread);
    }
    return closingStep(2.0 * w, 2.0 * acc, fraction * smallest);
  }
  for (std::size_t a = 0; a < bounds.size(); ++a) {
    if (bounds[a].empty) continue;
    for (std::size_t b = a + 1; b < bounds.size(); ++b) {
      if (bounds[b].empty) continue;
      const ObjectBounds &A = bounds[a], &B = bounds[b];
      const double gap = std::max(0.0, norm(A.centre - B.centre) - A.radius - B.radius);
      const double w = norm(A.velocity - B.velocity) + A.velocitySpread + B.velocitySpread;
      const double acc =
          norm(A.acceleration - B.acceleration) + A.accelerationSpread + B.accelerationSpread;
      step = std::min(
          step, closingStep(w, acc, gap + fraction * std::min(A.smallestRadius, B.smallestRadius)));
    }
  }
  return step;
}

}  // namespace

double approachStepBound(const Model& model, const State& state, const std::vector<Vec3>& force,
                         double fraction) {
  // MODEL §4.4. A pair closing at speed w with relative acceleration a may use
  // δ with w δ + ½ a δ² ≤ D, D = gap + fraction × r (closingStep).
  const ParticleIndex n = model.particleCount();
  double step = std::numeric_limits<double>::infinity();
  if (n == 0) return step;
  const auto acceleration = [&](ParticleIndex i) {
    return model.isFixed(i) ? Vec3{} : force[i] * model.inverseMass[i];
  };
  const Environment& env = model.environment;
  const bool solidEnvironment =
      !env.heightfields.empty() || !env.boxes.empty() || !env.spheres.empty();
  // A particle against the environment (fixed particles move kinematically and
  // do not collide with it).
  const auto againstEnvironment = [&](ParticleIndex i, const Vec3& v, const Vec3& a) {
    const double reach = fraction * model.radius[i];
    // Against the planes: the speed along the normal, beyond the gap.
    for (const GroundPlane& plane : env.planes) {
      const double gap =
          std::max(0.0, dot(state.position[i] - plane.point, plane.normal) - model.radius[i]);
      const double w = -dot(v, plane.normal), an = -dot(a, plane.normal);
      if (w <= 0.0 && an <= 0.0) continue;
      step = std::min(step, closingStep(std::max(w, 0.0), std::max(an, 0.0), gap + reach));
    }
    // Against the other environment items: the full speed.
    if (solidEnvironment) step = std::min(step, closingStep(norm(v), norm(a), reach));
  };
  // Particles [begin, end) against the environment only (no object bounds).
  const auto environmentOnly = [&](ParticleIndex begin, ParticleIndex end) {
    for (ParticleIndex i = begin; i < end; ++i)
      if (model.moves(i)) againstEnvironment(i, state.velocity[i], acceleration(i));
  };
  // Objects against each other, through their bounds: two particles of objects
  // A and B close at most at |V_A − V_B| + s_A + s_B (velocity differences
  // only: no observer enters), beyond the gap between the objects' spheres.
  // (Particles of one object are not bounded against each other: they are tied
  // by connectors, and self-contacts are between neighbours.)
  const auto objects = static_cast<std::size_t>(std::max<std::int32_t>(
      1, *std::max_element(model.objectOf.begin(), model.objectOf.end()) + 1));
  if (objects < 2) {
    environmentOnly(0, n);
    return step;
  }
  // Per-object scratch, kept per thread (no allocation once grown).
  struct Scratch {
    std::vector<ObjectBounds> bounds;
    std::vector<Vec3> vLow, vHigh, aLow, aHigh, pSum;
    std::vector<double> count;
    std::vector<char> virtualObject;  // goals' copies, paths' ends: they touch nothing
  };
  thread_local Scratch scratch;
  auto& [bounds, vLow, vHigh, aLow, aHigh, pSum, count, virtualObject] = scratch;
  bounds.assign(objects, ObjectBounds{});
  for (std::vector<Vec3>* v : {&vLow, &vHigh, &aLow, &aHigh, &pSum}) v->assign(objects, Vec3{});
  count.assign(objects, 0.0);
  virtualObject.assign(objects, 0);
  for (std::size_t o = 0; o < objects && o < model.objects.size(); ++o)
    virtualObject[o] = model.objects[o].contact.touches ? 0 : 1;
  // The particles go by runs of one object (an object's particles are usually
  // one run): a run's bounds are kept in locals, not read back from memory
  // particle by particle. The same operations in the same order per object.
  const auto runEnd = [&](ParticleIndex i) {
    ParticleIndex end = i + 1;
    while (end < n && model.objectOf[end] == model.objectOf[i]) ++end;
    return end;
  };
  for (ParticleIndex i = 0; i < n;) {
    const ParticleIndex end = runEnd(i);
    const auto o = static_cast<std::size_t>(std::max<std::int32_t>(0, model.objectOf[i]));
    if (model.objectOf[i] >= 0 && virtualObject[o] != 0) {
      environmentOnly(i, end);
      i = end;
      continue;
    }
    Vec3 lowV = vLow[o], highV = vHigh[o], lowA = aLow[o], highA = aHigh[o], sum = pSum[o];
    double counted = count[o];
    for (; i < end; ++i) {
      const Vec3& v = state.velocity[i];
      const Vec3 a = acceleration(i);
      if (model.moves(i)) againstEnvironment(i, v, a);
      if (counted == 0.0) {
        lowV = highV = v;
        lowA = highA = a;
      }
      lowV = {std::min(lowV.x, v.x), std::min(lowV.y, v.y), std::min(lowV.z, v.z)};
      highV = {std::max(highV.x, v.x), std::max(highV.y, v.y), std::max(highV.z, v.z)};
      lowA = {std::min(lowA.x, a.x), std::min(lowA.y, a.y), std::min(lowA.z, a.z)};
      highA = {std::max(highA.x, a.x), std::max(highA.y, a.y), std::max(highA.z, a.z)};
      sum += state.position[i];
      counted += 1.0;
    }
    vLow[o] = lowV;
    vHigh[o] = highV;
    aLow[o] = lowA;
    aHigh[o] = highA;
    pSum[o] = sum;
    count[o] = counted;
  }
  for (std::size_t o = 0; o < objects; ++o) {
    if (count[o] == 0.0) continue;
    bounds[o].empty = false;
    bounds[o].centre = pSum[o] / count[o];
    bounds[o].velocity = (vLow[o] + vHigh[o]) * 0.5;
    bounds[o].acceleration = (aLow[o] + aHigh[o]) * 0.5;
  }
  // The spreads as squares first (the square root of the largest square is the
  // largest root: the same bits). A virtual object's bounds stay empty.
  for (ParticleIndex i = 0; i < n;) {
    const ParticleIndex end = runEnd(i);
    ObjectBounds& b =
        bounds[static_cast<std::size_t>(std::max<std::int32_t>(0, model.objectOf[i]))];
    if (b.empty) {
      i = end;
      continue;
    }
    double radius = b.radius, velocitySpread = b.velocitySpread,
           accelerationSpread = b.accelerationSpread, smallestRadius = b.smallestRadius;
    for (; i < end; ++i) {
      radius = std::max(radius, norm(state.position[i] - b.centre) + model.radius[i]);
      velocitySpread = std::max(velocitySpread, squaredNorm(state.velocity[i] - b.velocity));
      accelerationSpread =
          std::max(accelerationSpread, squaredNorm(acceleration(i) - b.acceleration));
      smallestRadius = std::min(smallestRadius, model.radius[i]);
    }
    b.radius = radius;
    b.velocitySpread = velocitySpread;
    b.accelerationSpread = accelerationSpread;
    b.smallestRadius = smallestRadius;
  }
  for (ObjectBounds& b : bounds) {
    b.velocitySpread = std::sqrt(b.velocitySpread);
    b.accelerationSpread = std::sqrt(b.accelerationSpread);
  }
  return std::min(step, objectPairsStep(bounds, fraction));
}

namespace detail {

double boxRun(const Model& model, const State& state, const std::vector<Vec3>& force,
              ParticleIndex begin, ParticleIndex end, ObjectBox& box) {
  const auto accelerationOf = [&](ParticleIndex i) {
    return model.isFixed(i) ? Vec3{} : force[i] * model.inverseMass[i];
  };
  if (box.count == 0.0) {
    box.pLow = box.pHigh = state.position[begin];
    box.vLow = box.vHigh = state.velocity[begin];
    box.aLow = box.aHigh = accelerationOf(begin);
  }
  Vec3 pLow = box.pLow, pHigh = box.pHigh, vLow = box.vLow, vHigh = box.vHigh, aLow = box.aLow,
       aHigh = box.aHigh, sum = box.pSum;
  double count = box.count, smallest = box.smallestRadius, largest = box.largestRadius, every = 0.0;
  bool anyFree = box.anyFree;
  for (ParticleIndex i = begin; i < end; ++i) {
    const Vec3& p = state.position[i];
    const Vec3& v = state.velocity[i];
    const Vec3 a = accelerationOf(i);
    pLow = {std::min(pLow.x, p.x), std::min(pLow.y, p.y), std::min(pLow.z, p.z)};
    pHigh = {std::max(pHigh.x, p.x), std::max(pHigh.y, p.y), std::max(pHigh.z, p.z)};
    vLow = {std::min(vLow.x, v.x), std::min(vLow.y, v.y), std::min(vLow.z, v.z)};
    vHigh = {std::max(vHigh.x, v.x), std::max(vHigh.y, v.y), std::max(vHigh.z, v.z)};
    aLow = {std::min(aLow.x, a.x), std::min(aLow.y, a.y), std::min(aLow.z, a.z)};
    aHigh = {std::max(aHigh.x, a.x), std::max(aHigh.y, a.y), std::max(aHigh.z, a.z)};
    sum += p;
    count += 1.0;
    smallest = std::min(smallest, model.radius[i]);
    largest = std::max(largest, model.radius[i]);
    anyFree = anyFree || model.moves(i);
    every += (p.x + p.y + p.z) + (v.x + v.y + v.z) + (a.x + a.y + a.z);
  }
  box = {pLow, pHigh, vLow, vHigh, aLow, aHigh, sum, count, smallest, largest, anyFree};
  return every;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) double boxRunLanes(const Model& model, const State& state,
                                                   const std::vector<Vec3>& force,
                                                   ParticleIndex begin, ParticleIndex end,
                                                   ObjectBox& box) {
  // (No lambdas: they would not be compiled for AVX2.)
  const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
  const __m256d zero = _mm256_setzero_pd();
  const Vec3* position = state.position.data();
  const Vec3* velocity = state.velocity.data();
  const Vec3* f = force.data();
  const double* inverseMass = model.inverseMass.data();
  const double* radius = model.radius.data();
  __m256d pLow, pHigh, vLow, vHigh, aLow, aHigh;
  if (box.count == 0.0) {
    pLow = pHigh = _mm256_maskload_pd(&position[begin].x, xyz);
    vLow = vHigh = _mm256_maskload_pd(&velocity[begin].x, xyz);
    aLow = aHigh = inverseMass[begin] == 0.0 ? zero
                                             : _mm256_mul_pd(_mm256_maskload_pd(&f[begin].x, xyz),
                                                             _mm256_set1_pd(inverseMass[begin]));
  } else {
    pLow = _mm256_maskload_pd(&box.pLow.x, xyz);
    pHigh = _mm256_maskload_pd(&box.pHigh.x, xyz);
    vLow = _mm256_maskload_pd(&box.vLow.x, xyz);
    vHigh = _mm256_maskload_pd(&box.vHigh.x, xyz);
    aLow = _mm256_maskload_pd(&box.aLow.x, xyz);
    aHigh = _mm256_maskload_pd(&box.aHigh.x, xyz);
  }
  __m256d sum = _mm256_maskload_pd(&box.pSum.x, xyz), every = zero;
  double count = box.count, smallest = box.smallestRadius, largest = box.largestRadius;
  bool anyFree = box.anyFree;
  for (ParticleIndex i = begin; i < end; ++i) {
    const __m256d p = _mm256_maskload_pd(&position[i].x, xyz);
    const __m256d v = _mm256_maskload_pd(&velocity[i].x, xyz);
    const __m256d a = inverseMass[i] == 0.0 ? zero
                                            : _mm256_mul_pd(_mm256_maskload_pd(&f[i].x, xyz),
                                                            _mm256_set1_pd(inverseMass[i]));
    pLow = _mm256_min_pd(pLow, p);
    pHigh = _mm256_max_pd(pHigh, p);
    vLow = _mm256_min_pd(vLow, v);
    vHigh = _mm256_max_pd(vHigh, v);
    aLow = _mm256_min_pd(aLow, a);
    aHigh = _mm256_max_pd(aHigh, a);
    sum = _mm256_add_pd(sum, p);
    every = _mm256_add_pd(every, _mm256_add_pd(_mm256_add_pd(p, v), a));
    count += 1.0;
    smallest = std::min(smallest, radius[i]);
    largest = std::max(largest, radius[i]);
    anyFree = anyFree || inverseMass[i] != 0.0 || model.isCarried(i);
  }
  _mm256_maskstore_pd(&box.pLow.x, xyz, pLow);
  _mm256_maskstore_pd(&box.pHigh.x, xyz, pHigh);
  _mm256_maskstore_pd(&box.vLow.x, xyz, vLow);
  _mm256_maskstore_pd(&box.vHigh.x, xyz, vHigh);
  _mm256_maskstore_pd(&box.aLow.x, xyz, aLow);
  _mm256_maskstore_pd(&box.aHigh.x, xyz, aHigh);
  _mm256_maskstore_pd(&box.pSum.x, xyz, sum);
  box.count = count;
  box.smallestRadius = smallest;
  box.largestRadius = largest;
  box.anyFree = anyFree;
  alignas(32) double lanes[4];
  _mm256_store_pd(lanes, every);
  return lanes[0] + lanes[1] + lanes[2];
}
#endif

bool haveBoxRunLanes() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return avx2;
#else
  return false;
#endif
}

}  // namespace detail

namespace {

double largestMagnitude(const Vec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

// `x` raised past the round-off of the sums it bounds: relative 1e-9 and
// 1e-12 of `scale`, the magnitude of the numbers they were taken from (far
// above a few units in the last place of either).
double raised(double x, double scale) { return x * (1.0 + 1e-9) + 1e-12 * scale; }

}  // namespace

double approachStepFloor(const Model& model, const State& state, const std::vector<Vec3>& force,
                         double fraction) {
  // approachStepBound's closing speeds and accelerations bounded from above and
  // its gaps from below, from the same centres of mass and box centres (the
  // same bits). closingStep grows with the gap and shrinks with the speed and
  // the acceleration; the result is lowered by 1e-9 for its rounding.
  const ParticleIndex n = model.particleCount();
  if (n == 0) return std::numeric_limits<double>::infinity();
  const auto objects = static_cast<std::size_t>(std::max<std::int32_t>(
      1, *std::max_element(model.objectOf.begin(), model.objectOf.end()) + 1));
  const auto isVirtual = [&](std::size_t o) {
    return o < model.objects.size() && !model.objects[o].contact.touches;
  };
  // The boxes, each reset at its object's first run in this call (a stamp per
  // object): a pile of single balls has as many objects as particles, and a
  // pass resetting them all cost as much as filling them.
  thread_local std::vector<detail::ObjectBox> boxes;
  thread_local std::vector<std::uint64_t> stamps;
  thread_local std::uint64_t call = 0;
  ++call;
  if (boxes.size() < objects) {
    boxes.resize(objects);
    stamps.resize(objects, 0);
  }
  const bool lanes = detail::haveBoxRunLanes();
  bool unowned = false;  // particles of no object: approachStepBound counts them in object 0
  double every = 0.0;    // not finite when a number is not
  // By runs of one object (an object's particles are usually one run).
  for (ParticleIndex i = 0; i < n;) {
    ParticleIndex end = i + 1;
    while (end < n && model.objectOf[end] == model.objectOf[i]) ++end;
    unowned = unowned || model.objectOf[i] < 0;
    const auto object = static_cast<std::size_t>(std::max<std::int32_t>(0, model.objectOf[i]));
    detail::ObjectBox& box = boxes[object];
    if (stamps[object] != call) {
      stamps[object] = call;
      box.clear();
    }
#if defined(__x86_64__) && defined(__GNUC__)
    every += lanes ? detail::boxRunLanes(model, state, force, i, end, box)
                   : detail::boxRun(model, state, force, i, end, box);
#else
    every += detail::boxRun(model, state, force, i, end, box);
#endif
    i = end;
  }
  // Left to approachStepBound: numbers that are not finite, and particles of no
  // object beside a virtual object 0 (its bounds are of those particles alone).
  if (!std::isfinite(every) || (unowned && isVirtual(0))) return 0.0;
  thread_local std::vector<ObjectBounds> bounds;
  bounds.resize(objects);  // (each set below)
  const Environment& env = model.environment;
  const bool solidEnvironment =
      !env.heightfields.empty() || !env.boxes.empty() || !env.spheres.empty();
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t o = 0; o < objects; ++o) {
    const detail::ObjectBox& box = boxes[o];
    if (stamps[o] != call || box.count == 0.0) {
      bounds[o] = ObjectBounds{};
      continue;
    }
    ObjectBounds b;
    b.empty = false;
    b.smallestRadius = box.smallestRadius;
    b.centre = box.pSum / box.count;
    b.velocity = (box.vLow + box.vHigh) * 0.5;
    b.acceleration = (box.aLow + box.aHigh) * 0.5;
    const Vec3 pMiddle = (box.pLow + box.pHigh) * 0.5, pHalf = (box.pHigh - box.pLow) * 0.5;
    const Vec3 vHalf = (box.vHigh - box.vLow) * 0.5, aHalf = (box.aHigh - box.aLow) * 0.5;
    // One particle: every box is a point, the centre is it (p / 1, (p + p) / 2),
    // and the four norms are of zero vectors: 0 (the same bits without them).
    const bool point = box.count == 1.0;
    b.radius = raised(raised(point ? 0.0 : norm(b.centre - pMiddle) + norm(pHalf),
                             largestMagnitude(b.centre) + largestMagnitude(pMiddle)) +
                          box.largestRadius,
                      0.0);
    b.velocitySpread = raised(point ? 0.0 : norm(vHalf), largestMagnitude(b.velocity));
    b.accelerationSpread = raised(point ? 0.0 : norm(aHalf), largestMagnitude(b.acceleration));
    // (A virtual object touches nothing: its bounds stay empty, as in approachStepBound.)
    bounds[o] = isVirtual(o) ? ObjectBounds{} : b;
    if (!box.anyFree) continue;
    // The object's free particles against the environment (its box of fixed
    // and free particles bounds them).
    const double reach = fraction * box.smallestRadius;
    for (const GroundPlane& plane : env.planes) {
      const Vec3& m = plane.normal;
      const auto across = [&](const Vec3& half) {
        return std::abs(m.x) * half.x + std::abs(m.y) * half.y + std::abs(m.z) * half.z;
      };
      const double reachOfNormal = 1.0 + norm(m);
      const double w = -dot(b.velocity, m), an = -dot(b.acceleration, m);
      const double wUp = w + across(vHalf) + 1e-9 * (std::abs(w) + across(vHalf)) +
                         1e-12 * largestMagnitude(b.velocity) * reachOfNormal;
      const double aUp = an + across(aHalf) + 1e-9 * (std::abs(an) + across(aHalf)) +
                         1e-12 * largestMagnitude(b.acceleration) * reachOfNormal;
      if (wUp <= 0.0 && aUp <= 0.0) continue;  // every particle recedes
      const double height = dot(pMiddle - plane.point, m) - across(pHalf) - box.largestRadius;
      const double gapDown =
          height - 1e-9 * (std::abs(height) + across(pHalf) + box.largestRadius) -
          1e-12 * (largestMagnitude(pMiddle) + largestMagnitude(plane.point)) * reachOfNormal;
      step = std::min(step, closingStep(std::max(wUp, 0.0), std::max(aUp, 0.0),
                                        std::max(0.0, gapDown) + reach));
    }
    if (solidEnvironment) {
      step = std::min(step,
                      closingStep(raised(norm(b.velocity) + b.velocitySpread, 0.0),
                                  raised(norm(b.acceleration) + b.accelerationSpread, 0.0), reach));
    }
  }
  if (objects >= 2) step = std::min(step, objectPairsStep(bounds, fraction));
  return step * (1.0 - 1e-9);
}

double approachStepQuickFloor(const Model& model, const State& state,
                              const std::vector<Vec3>& force, double fraction) {
  const ParticleIndex n = model.particleCount();
  if (n == 0) return std::numeric_limits<double>::infinity();
  const Vec3* v = state.velocity.data();
  const Vec3* f = force.data();
  const double* inverseMass = model.inverseMass.data();
  const double* radius = model.radius.data();
  double velocity = 0.0, acceleration = 0.0, smallest = std::numeric_limits<double>::infinity();
  double every = 0.0;  // not finite when a number is not
  for (ParticleIndex i = 0; i < n; ++i) {
    const double im = inverseMass[i];
    const Vec3 a = f[i] * im;  // (0 for a fixed particle: im is 0)
    velocity = std::max({velocity, std::abs(v[i].x), std::abs(v[i].y), std::abs(v[i].z)});
    acceleration = std::max({acceleration, std::abs(a.x), std::abs(a.y), std::abs(a.z)});
    smallest = std::min(smallest, radius[i]);
    every += (v[i].x + v[i].y + v[i].z) + (a.x + a.y + a.z);
  }
  if (!std::isfinite(every)) return 0.0;
  // |V_A - V_B| <= 2√3 c and each spread <= √3 c; a particle against the
  // environment <= √3 c. 4√3 = 6.9282..., raised to 6.93 and for round-off.
  constexpr double kReach = 6.93;
  const double w = raised(kReach * velocity, 0.0), a = raised(kReach * acceleration, 0.0);
  return closingStep(w, a, fraction * smallest) * (1.0 - 1e-9);
}

namespace {

// The approach bound where it may bind: infinite (no cap) when a floor of it
// is at least `others`, the other caps of the step, which it then cannot
// undercut (the whole scene's quick floor first, then the objects' floor).
double approachLimitBelow(double others, const Model& model, const State& state,
                          const std::vector<Vec3>& force, double fraction) {
  if (approachStepQuickFloor(model, state, force, fraction) >= others ||
      approachStepFloor(model, state, force, fraction) >= others)
    return std::numeric_limits<double>::infinity();
  return approachStepBound(model, state, force, fraction);
}

}  // namespace

StepStatus stepWithoutTunnelling(World& world, double dt, double fraction, double contactSafety,
                                 std::int64_t* splits, std::int64_t maxSubsteps,
                                 const std::atomic<bool>* stop) {
  const double end = world.state().time + dt;
  double left = dt;
  for (std::int64_t taken = 0;; ++taken) {
    // Bounded work: the limit and a requested stop end the step between substeps.
    if ((maxSubsteps > 0 && taken >= maxSubsteps) ||
        (stop != nullptr && stop->load(std::memory_order_relaxed)))
      return StepStatus::kStopped;
    const Evaluation& evaluation = world.evaluation();
    const double contactBound = contactSafety > 0.0 ? contactSafety * evaluation.contactCriticalStep
                                                    : std::numeric_limits<double>::infinity();
    const double bound =
        std::min(contactBound, approachLimitBelow(std::min(left, contactBound), world.model(),
                                                  world.state(), evaluation.force, fraction));
    const double pieces = bound >= left ? 1.0 : std::ceil(left / bound);
    if (!(pieces < 1e9)) return StepStatus::kNonFinite;  // nothing finite can be done
    const bool last = pieces <= 1.0;
    if (!last && splits) ++*splits;
    const StepStatus status = world.step(last ? left : left / pieces);
    if (status != StepStatus::kOk || last) return status;
    left = end - world.state().time;
    if (!(left > 0.0)) return status;
  }
}

namespace {

// Throws std::invalid_argument naming the first setting out of its range.
const AdaptiveStepSettings& checked(const AdaptiveStepSettings& s) {
  const auto require = [](bool ok, const char* name, double value, const char* range) {
    if (!ok || !std::isfinite(value))
      throw std::invalid_argument(
          detail::text("AdaptiveStepSettings::{} = {} must be {}", name, value, range));
  };
  require(s.initialStep > 0.0, "initialStep", s.initialStep, "> 0 (s)");
  require(s.minStep >= 0.0, "minStep", s.minStep, ">= 0 (s; 0: relative to the first step)");
  require(s.jumpLimit >= 0.0, "jumpLimit", s.jumpLimit, ">= 0 (-; 0: no jump is taken)");
  require(s.maxStep >= s.minStep && s.maxStep > 0.0, "maxStep",
          std::isinf(s.maxStep) ? 1.0 : s.maxStep, "> 0 and >= minStep (s; infinite: none)");
  require(s.energyTolerance > 0.0, "energyTolerance", s.energyTolerance, "> 0");
  require(s.lossToleranceFactor >= 0.0, "lossToleranceFactor", s.lossToleranceFactor, ">= 0");
  require(s.energyFloor >= 0.0, "energyFloor", s.energyFloor, ">= 0 (J)");
  require(s.shrinkFactor > 0.0 && s.shrinkFactor < 1.0, "shrinkFactor", s.shrinkFactor,
          "in (0, 1)");
  require(s.growFactor >= 1.0, "growFactor", s.growFactor, ">= 1");
  require(s.safety > 0.0 && s.safety <= 1.0, "safety", s.safety, "in (0, 1]");
  require(s.errorOrder >= 0.0, "errorOrder", s.errorOrder, ">= 0 (0: from the integrator)");
  require(s.maxPenetrationFraction >= 0.0, "maxPenetrationFraction", s.maxPenetrationFraction,
          ">= 0");
  require(s.maxApproachFraction > 0.0, "maxApproachFraction", s.maxApproachFraction, "> 0");
  require(s.stabilitySafety > 0.0, "stabilitySafety", s.stabilitySafety, "> 0");
  require(s.maxRejectionsInARow >= 1, "maxRejectionsInARow", s.maxRejectionsInARow, ">= 1");
  return s;
}

}  // namespace

AdaptiveStepper::AdaptiveStepper(const Model& model, AdaptiveStepSettings settings)
    : settings_(checked(settings)) {
  const StabilityEstimate estimate = estimateStability(model);
  stabilityLimit_ = settings_.stabilitySafety * estimate.criticalStep;
  taylorStep_ = estimate.taylorStep;
  stabilityOmega_ = estimate.omegaMax;
  stabilityDamping_ = estimate.dampingRate;
  step_ = std::min({settings_.initialStep, settings_.maxStep, stabilityLimit_});
  minStep_ = settings_.minStep > 0.0 ? settings_.minStep : 1.0e-8 * step_;
  stats_.smallestStep = std::numeric_limits<double>::infinity();
}

double AdaptiveStepper::proposal(double error) const {
  const double ratio = settings_.energyTolerance / std::max(std::abs(error), 1e-300);
  return settings_.safety * std::pow(ratio, 1.0 / errorOrder_);
}

double AdaptiveStepper::energyError(const EnergyTally& before, const EnergyTally& after,
                                    double activeBefore, double activeAfter) const {
  // MODEL §4.1: error = (ΔE + ΔW_dissipated - ΔW_external) / scale, where
  // W_dissipated is the work of damping, friction and viscosity, W_external that
  // of fixed particles moved kinematically, and the scale is the largest of the
  // active energy (in the scene's frame) before and after, the gravity scale
  // and the optional absolute floor. Energy changes within the round-off of the
  // sums (energyRoundoffScale) are no error: that band is taken off |created|.
  // No term sees the observer's velocity or the datum except that band.
  // (The rigid trees' implicit contact loads' scheme loss is booked in the
  // account's dissipated work but is integration error: it counts here.)
  const double created =
      (after.mechanical() - before.mechanical()) +
      ((after.dissipated - after.implicitLoss) - (before.dissipated - before.implicitLoss)) -
      (after.external - before.external);
  const double roundoff = std::max(energyRoundoffScale(before), energyRoundoffScale(after));
  if (std::abs(created) <= roundoff) return 0.0;
  const double beyond = created > 0.0 ? created - roundoff : created + roundoff;
  const double scale = std::max({activeBefore, activeAfter, gravityScale_, settings_.energyFloor});
  if (!(scale > 0.0))
    return beyond > 0.0 ? std::numeric_limits<double>::infinity()
                        : -std::numeric_limits<double>::infinity();
  return beyond / scale;
}

bool AdaptiveStepper::Measured::holdsFor(const World& w) const {
  return world == &w && changes == w.changeCount() && step == w.state().stepCount &&
         time == w.state().time;
}

AdaptiveStepResult AdaptiveStepper::advance(World& world, double maxDt,
                                            const std::atomic<bool>* stop) {
  AdaptiveStepResult result;
  world.refresh();
  if (!refinedLimit_) {
    // The tighter estimate needs positions: refine at the first step. (Edits
    // that stiffen the model later are not re-estimated: a joint limit that
    // engages and releases every few steps would pay a power iteration each
    // time; the energy test rejects a step that is too large for them.)
    refinedLimit_ = true;
    const StabilityEstimate refined = estimateStability(world.model(), &world.state().position);
    if (settings_.stabilitySafety * refined.criticalStep > stabilityLimit_) {
      stabilityLimit_ = settings_.stabilitySafety * refined.criticalStep;
      stabilityOmega_ = refined.omegaMax;
      stabilityDamping_ = refined.dampingRate;
    }
    // The paper's Taylor scheme is stable only below its own bound, set by the
    // damping (StabilityEstimate::taylorStep; the larger of the two estimates',
    // as above); without damping it has none, and the energy test judges.
    taylorStep_ = std::max(taylorStep_, refined.taylorStep);
    if (world.integrator() == Integrator::kTaylor && taylorStep_ > 0.0) {
      stabilityLimit_ = std::min(stabilityLimit_, settings_.stabilitySafety * taylorStep_);
      step_ = std::min(step_, stabilityLimit_);
    }
  }
  if (errorOrder_ <= 0.0) {
    errorOrder_ = settings_.errorOrder > 0.0                          ? settings_.errorOrder
                  : world.integrator() == Integrator::kVelocityVerlet ? 3.0
                                                                      : 2.0;
  }
  if (gravityScale_ < 0.0) gravityScale_ = gravityEnergyScale(world.model(), world.state());
  if (!(step_ >= minStep_)) {
    result.ok = false;
    result.failure = detail::text(
        "the adaptive step {:.3g} s is below its floor {:.3g} s before any trial (the "
        "stability estimate allows {:.3g} s): {}",
        step_, minStep_, stabilityLimit_, diagnose(world, &result.particle));
    return result;
  }
  saved_ = world.snapshot();
  const EnergyTally energyBefore = saved_.energy();
  // The state the last accepted step ended at, unchanged: what it measured there.
  const bool measured = after_.holdsFor(world);
  const double activeBefore =
      measured ? after_.activeEnergy : activeEnergy(world.model(), saved_.state(), energyBefore);
  const double penetrationBefore =
      measured ? after_.penetration
      : settings_.maxPenetrationFraction > 0.0
          ? deepestPenetrationFraction(world.model(), saved_.evaluation().contacts)
          : 0.0;
  // The touching contacts' own stability limit (they are not in the model's).
  const double contactLimit = settings_.stabilitySafety * saved_.evaluation().contactCriticalStep;
  // The joint drives' damping on top of the connectors' (Weyl): it is not in the
  // model's estimate, as a run's control changes the drives' gains.
  const double driveRate = saved_.evaluation().driveDampingRate;
  const double driveLimit =
      driveRate > 0.0 ? settings_.stabilitySafety *
                            dampedCriticalStep(stabilityOmega_, stabilityDamping_ + driveRate)
                      : std::numeric_limits<double>::infinity();
  // No pair of approaching surfaces may pass through each other (MODEL §4.4).
  // (Against the other limits as they are now: the trials below only shrink the step.)
  const double approachLimit =
      approachLimitBelow(std::min({step_, maxDt, contactLimit, driveLimit}), world.model(),
                         saved_.state(), saved_.evaluation().force, settings_.maxApproachFraction);
  // The floor holds for the model's own limits too (not for the time left to
  // the end): a step they hold below it is a stall, not a crawl of ever smaller steps.
  if (const double limit = std::min({contactLimit, driveLimit, approachLimit});
      limit < minStep_ && limit < maxDt) {
    result.ok = false;
    const char* which = limit == contactLimit ? "the touching contacts' stability limit"
                        : limit == driveLimit ? "the joint drives' damping limit"
                                              : "the approach bound (MODEL §4.4)";
    result.failure = detail::text(
        "{} allows a step of {:.3g} s, below the adaptive step's floor {:.3g} s, at t = {:.6g} "
        "s: {}",
        which, limit, minStep_, saved_.state().time, diagnose(world, &result.particle));
    return result;
  }
  for (;;) {
    const double dt = std::min({step_, maxDt, contactLimit, driveLimit, approachLimit});
    const StepStatus status = world.step(dt);
    const bool finite = status == StepStatus::kOk;
    const double activeAfter =
        finite ? activeEnergy(world.model(), world.state(), world.energy()) : 0.0;
    const double error = finite
                             ? energyError(energyBefore, world.energy(), activeBefore, activeAfter)
                             : std::numeric_limits<double>::infinity();
    // Geometric control (MODEL §4): one step may not push the deepest contact
    // further in by more than the set fraction of a radius. (The depth a soft
    // contact reaches at rest is physics, set by κ_c, and is not capped.)
    const double penetrationAfter =
        finite && settings_.maxPenetrationFraction > 0.0
            ? deepestPenetrationFraction(world.model(), world.contacts())
            : 0.0;
    const bool tooDeep = finite && settings_.maxPenetrationFraction > 0.0 &&
                         penetrationAfter - penetrationBefore > settings_.maxPenetrationFraction;
    bool accepted = !tooDeep && error <= settings_.energyTolerance &&
                    error >= -settings_.lossToleranceFactor * settings_.energyTolerance;
    if (!accepted && !tooDeep && std::isfinite(error)) {
      // A jump of the potential (jumpLimit): the same error from trials 16-fold
      // apart in size, in this call or an earlier one (steps that stop short of
      // the jump are accepted, so that the trials close in on it over several
      // calls). No step removes it: this trial takes it.
      const double now = saved_.state().time;
      if (now <= jumpTime_ + jumpTrial_ &&
          std::abs(error - jumpError_) <= 0.1 * std::abs(jumpError_)) {
        if (std::abs(error) <= settings_.jumpLimit && dt * 16.0 <= jumpTrial_) {
          accepted = true;
          result.jumped = true;
        }
      } else {
        jumpError_ = error;
        jumpTrial_ = dt;
        jumpTime_ = now;
      }
    }
    if (accepted) {
      after_ = {&world,      world.changeCount(), world.state().stepCount, world.state().time,
                activeAfter, penetrationAfter};
      result.dt = dt;
      result.energyError = error;
      ++stats_.accepted;
      stats_.smallestStep = std::min(stats_.smallestStep, dt);
      stats_.largestStep = std::max(stats_.largestStep, dt);
      stats_.sumOfSteps += dt;
      stats_.lastEnergyError = error;
      stats_.lastStep = dt;
      // What set the step (the caps in the order of the trial's min).
      if (result.jumped) {
        ++stats_.setByJump;
      } else if (dt == step_) {
        if (step_ == stabilityLimit_)
          ++stats_.setByConnectors;
        else if (step_ == settings_.maxStep)
          ++stats_.setByMaxStep;
        else
          ++stats_.setByError;
      } else if (dt == contactLimit) {
        ++stats_.setByContacts;
      } else if (dt == driveLimit) {
        ++stats_.setByConnectors;
      } else if (dt == approachLimit) {
        ++stats_.setByApproach;
      } else {
        ++stats_.setByTimeLeft;
      }
      // Grow when the error leaves room: δ · safety · (tol/|e|)^(1/p), at most × growFactor.
      // (The carried step grows from at most growFactor × the trial: a cap that
      // held the trial down for long does not leave an unbounded step behind.)
      if (result.jumped) {
        // The jump tells nothing of the steps beyond it: the next trial is the
        // first one of this call again (else a few jumps in a row hold the step
        // at the floor, where no jump can be told from the step's error).
        step_ = std::min(jumpTrial_, stabilityLimit_);
        jumpError_ = 0.0;
        return result;
      }
      step_ = std::min(step_, dt * settings_.growFactor);
      step_ = std::min({step_ * std::clamp(proposal(error), 1.0, settings_.growFactor),
                        settings_.maxStep, stabilityLimit_});
      return result;
    }
    // Reject: restore the copy, shrink (at least halve), retry.
    ++stats_.rejected;
    ++result.rejections;
    step_ = dt * std::clamp(tooDeep ? settings_.shrinkFactor : proposal(error), 0.1,
                            settings_.shrinkFactor);
    const bool stalled = step_ < minStep_ || result.rejections >= settings_.maxRejectionsInARow;
    // The failed trial's diagnosis, and the particle it blames.
    const std::string why = stalled ? diagnose(world, &result.particle) : std::string();
    world.restore(saved_);
    if (stalled) {
      result.ok = false;
      result.failure = detail::text(
          "the adaptive step fell to {:.3g} s (floor {:.3g} s) after {} rejections at t = {:.6g} "
          "s: {}",
          step_, minStep_, result.rejections, saved_.state().time, why);
      return result;
    }
    if (stop != nullptr && stop->load(std::memory_order_relaxed)) {
      result.ok = false;
      result.stopped = true;
      return result;
    }
  }
}

std::string AdaptiveStepper::diagnose(const World& world, ParticleIndex* blamed) const {
  // Where the trial went wrong: the particle with the largest acceleration and
  // the connector holding the most energy.
  const Model& model = world.model();
  const State& state = world.state();
  const Evaluation& evaluation = world.evaluation();
  ParticleIndex worst = kNoParticle;
  double worstAcceleration = -1.0;
  for (ParticleIndex i = 0; i < model.particleCount(); ++i) {
    const double a = norm(evaluation.force[i]) * model.inverseMass[i];
    if (!(a <= worstAcceleration)) {
      worstAcceleration = a;
      worst = i;
    }
  }
  if (blamed) *blamed = worst;
  std::string where;
  if (worst != kNoParticle) {
    const auto object = model.objectOf[worst];
    const std::string objectName =
        object >= 0 && object < static_cast<std::int32_t>(model.objects.size())
            ? model.objects[object].name
            : std::string("?");
    where = detail::text("particle {} (object '{}') has the largest acceleration, {:.3g} m/s²",
                         worst, objectName, worstAcceleration);
  }
  double worstEnergy = 0.0;
  std::string connector;
  for (std::size_t k = 0; k < model.linearSprings.size(); ++k) {
    const LinearSpring& s = model.linearSprings[k];
    const double e = linearSpringForce(s, state.position[s.a], state.position[s.b], {}, {}).energy;
    if (e > worstEnergy) {
      worstEnergy = e;
      connector = detail::text("LS {} (particles {}, {}) holds {:.3g} J", k, s.a, s.b, e);
    }
  }
  if (!connector.empty()) where += "; " + connector;
  if (evaluation.energy.contact > 0.0)
    where += detail::text("; contacts hold {:.3g} J", evaluation.energy.contact);
  return where;
}

}  // namespace robophi
