// Overlaps in the initial state (run/start_checks.h).
#include "run/start_checks.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <tuple>

#include "robophi/world.h"

namespace robophi {

namespace {

// "plane 0", "box 2": environment items are numbered planes, heightfields, boxes, spheres.
std::string environmentItemName(const Environment& env, std::int32_t item) {
  const auto planes = static_cast<std::int32_t>(env.planes.size());
  const auto fields = static_cast<std::int32_t>(env.heightfields.size());
  const auto boxes = static_cast<std::int32_t>(env.boxes.size());
  if (item < planes) return fmt::format("environment plane {}", item);
  if (item < planes + fields) return fmt::format("environment heightfield {}", item - planes);
  if (item < planes + fields + boxes)
    return fmt::format("environment box {}", item - planes - fields);
  return fmt::format("environment sphere {}", item - planes - fields - boxes);
}

struct Overlap {
  int pairs = 0;
  double depth = 0.0;     // deepest penetration (m), > 0
  double fraction = 0.0;  // of the smaller radius (-)
  double radius = 0.0;    // the smaller radius there (m)
  ParticleIndex a = 0, b = -1;
};

}  // namespace

std::vector<std::string> startingOverlapWarnings(const Model& model, const State& initial) {
  std::vector<std::string> warnings;
  if (!model.contact.enabled || model.particleCount() == 0) return warnings;
  World world(model, initial);
  world.refresh();
  auto objectOf = [&](ParticleIndex i) {
    return i >= 0 && static_cast<std::size_t>(i) < model.objectOf.size()
               ? model.objectOf[static_cast<std::size_t>(i)]
               : -1;
  };
  auto isVirtual = [&](std::int32_t o) {
    return o >= 0 && static_cast<std::size_t>(o) < model.objects.size() &&
           !model.objects[static_cast<std::size_t>(o)].contact.touches;
  };
  // Key: (object a, object b) or (object a, -1 - environment item).
  std::map<std::pair<std::int32_t, std::int32_t>, Overlap> overlaps;
  for (const Contact& c : world.contacts()) {
    const double depth = -c.depth;
    if (!(depth > 0.0)) continue;
    const std::int32_t oa = objectOf(c.a);
    if (isVirtual(oa)) continue;
    double smaller = model.radius[c.a];
    std::pair<std::int32_t, std::int32_t> key;
    if (c.withEnvironment()) {
      key = {oa, c.other};
    } else {
      // Pairs of one object too: the contact acts on them unless a connector
      // ties them (excluded pairs are not contacts), e.g. particles piled in one spot.
      const std::int32_t ob = objectOf(c.other);
      if (isVirtual(ob)) continue;
      smaller = std::min(smaller, model.radius[c.other]);
      key = {std::min(oa, ob), std::max(oa, ob)};
    }
    const double fraction = smaller > 0.0 ? depth / smaller : 0.0;
    if (!(fraction > kStartingOverlapFraction)) continue;
    Overlap& o = overlaps[key];
    ++o.pairs;
    if (depth > o.depth) {
      o.depth = depth;
      o.fraction = fraction;
      o.radius = smaller;
      o.a = c.a;
      o.b = c.other;
    }
  }
  auto objectName = [&](std::int32_t o) {
    return o >= 0 && static_cast<std::size_t>(o) < model.objects.size()
               ? fmt::format("object '{}'", model.objects[static_cast<std::size_t>(o)].name)
               : std::string("particles without an object");
  };
  // The largest overlaps first (most particle pairs); a scene of many
  // overlapping objects gets kMaxOverlapWarnings lines and a count of the rest.
  std::vector<std::pair<std::pair<std::int32_t, std::int32_t>, Overlap>> sorted(overlaps.begin(),
                                                                                overlaps.end());
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& x, const auto& y) { return x.second.pairs > y.second.pairs; });
  long long restPairs = 0;
  for (std::size_t k = kMaxOverlapWarnings; k < sorted.size(); ++k)
    restPairs += sorted[k].second.pairs;
  if (sorted.size() > kMaxOverlapWarnings) sorted.resize(kMaxOverlapWarnings);
  for (const auto& [key, o] : sorted) {
    if (key.first == key.second) {
      warnings.push_back(fmt::format(
          "particles of {} start overlapping each other: {} particle pair{} not tied by a "
          "connector, the deepest by {:.3g} m ({:.0f}% of the smaller radius {:.3g} m, particles "
          "{} and {}); the contact force will throw them apart at the first steps",
          objectName(key.first), o.pairs, o.pairs == 1 ? "" : "s", o.depth, 100.0 * o.fraction,
          o.radius, std::min(o.a, o.b), std::max(o.a, o.b)));
      continue;
    }
    if (key.second < 0) {
      warnings.push_back(fmt::format(
          "{} starts inside {}: {} particle{} overlap it, the deepest by {:.3g} m ({:.0f}% of "
          "its radius {:.3g} m, particle {}); the contact force will push it out at the first "
          "steps",
          objectName(key.first), environmentItemName(model.environment, -1 - key.second), o.pairs,
          o.pairs == 1 ? "" : "s", o.depth, 100.0 * o.fraction, o.radius, o.a));
    } else {
      warnings.push_back(fmt::format(
          "{} and {} start overlapping: {} particle pair{}, the deepest by {:.3g} m ({:.0f}% of "
          "the smaller radius {:.3g} m, particles {} and {}); the contact force will throw them "
          "apart at the first steps",
          objectName(key.first), objectName(key.second), o.pairs, o.pairs == 1 ? "" : "s", o.depth,
          100.0 * o.fraction, o.radius, std::min(o.a, o.b), std::max(o.a, o.b)));
    }
  }
  if (restPairs > 0) {
    warnings.push_back(
        fmt::format("and {} more pairs of objects start overlapping ({} particle pairs)",
                    overlaps.size() - kMaxOverlapWarnings, restPairs));
  }
  return warnings;
}

}  // namespace robophi
