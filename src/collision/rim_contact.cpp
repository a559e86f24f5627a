// Round rims: the closest point of a ring's circle to an environment item (the
// least signed distance over the circle: exact for a plane, else sampled and
// searched in each of its two lowest dips), then the torus of the particles'
// radius around it (MODEL §3.1 depth d = distance - r).
// Cylinder wheels (an imported robot's): the two edge circles of the cylinder
// about the axis its hub and axis particles give, each as a ring of tube 0.
// Round balls: the sphere of the ball's radius R about its particles' mass
// centre, d = distance(item, centre) - R, the contact point -n R from it.
// On a heightfield the distance is to the tangent plane at the contact point
// (a fixed point from the tangent plane below the centre), as a ring's.
#include "collision/rim_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/environment.h"

namespace robophi {

Vec3 rimCenter(const Model& model, const RimRing& rim, const std::vector<Vec3>& position) {
  Vec3 center;
  double mass = 0.0;
  for (std::int32_t k = rim.first; k < rim.first + rim.count; ++k) {
    center += position[static_cast<std::size_t>(k)] * model.mass[k];
    mass += model.mass[k];
  }
  return center / mass;
}

namespace {

struct Ring {
  Vec3 center, axis, start;  // start: unit direction to the ring's first particle
  double radius = 0.0;
};

Ring ringAt(const Model& model, const RimRing& rim, const std::vector<Vec3>& p) {
  Ring ring;
  ring.center = rimCenter(model, rim, p);
  Vec3 normal;
  double radius = 0.0;
  for (std::int32_t k = 0; k < rim.count; ++k) {
    const Vec3 r = p[rim.first + k] - ring.center;
    const Vec3 next = p[rim.first + (k + 1) % rim.count] - ring.center;
    normal += cross(r, next);
    radius += norm(r);
  }
  ring.radius = radius / rim.count;
  const double size = norm(normal);
  ring.axis = size > 0.0 ? normal / size : Vec3{0.0, 0.0, 1.0};
  const Vec3 first = p[rim.first] - ring.center;
  const Vec3 inPlane = first - ring.axis * dot(first, ring.axis);
  const double length = norm(inPlane);
  ring.start = length > 0.0 ? inPlane / length : Vec3{1.0, 0.0, 0.0};
  return ring;
}

// The circle point whose direction from the centre is most against `normal`.
Vec3 circlePointAgainst(const Ring& ring, const Vec3& normal) {
  Vec3 d = normal - ring.axis * dot(normal, ring.axis);
  const double length = norm(d);
  // A ring lying flat on the surface touches it all round: take its first particle's side.
  d = length > 1e-12 ? d / -length : ring.start;
  return ring.center + d * ring.radius;
}

// The circle point at `angle` from the ring's first particle's direction.
Vec3 circlePointAt(const Ring& ring, const Vec3& side, double angle) {
  return ring.center + (ring.start * std::cos(angle) + side * std::sin(angle)) * ring.radius;
}

// A point of the circle and the item's signed distance and normal there.
struct CirclePoint {
  Vec3 point, normal;
  double distance = std::numeric_limits<double>::infinity();
  /// A shallower dip's saddle: the least, over the two arcs to the deepest dip,
  /// of the arc's highest sampled distance (infinity for the deepest dip).
  double saddle = std::numeric_limits<double>::infinity();
  /// The depth of a contact of tube radius r here (< 0: touching): the distance
  /// less r, and for a shallower dip no deeper than it lies below its saddle.
  double depth(double r) const { return std::max(distance - r, distance - saddle); }
};

CirclePoint circleSample(const Environment& environment, std::int32_t e, const Ring& ring,
                         const Vec3& side, double angle) {
  CirclePoint c;
  c.point = circlePointAt(ring, side, angle);
  if (!environmentDistance(environment, e, c.point, c.distance, c.normal))
    c.distance = std::numeric_limits<double>::infinity();  // (not covered: no contact there)
  return c;
}

// The least distance over the arc [low, high] of the circle, by golden-section
// search (the arc holds one dip: it brackets a sample below its neighbours).
CirclePoint leastOnArc(const Environment& environment, std::int32_t e, const Ring& ring,
                       const Vec3& side, double low, double high) {
  constexpr double kGolden = 0.6180339887498949;
  // (The arc / 1.1e5: the least is found to ~1e-14 m on a wheel's circle, its error
  // second order in the place.)
  constexpr int kIterations = 24;
  double a = high - kGolden * (high - low), b = low + kGolden * (high - low);
  CirclePoint atA = circleSample(environment, e, ring, side, a);
  CirclePoint atB = circleSample(environment, e, ring, side, b);
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    if (atA.distance <= atB.distance) {
      high = b;
      b = a;
      atB = atA;
      a = high - kGolden * (high - low);
      atA = circleSample(environment, e, ring, side, a);
    } else {
      low = a;
      a = b;
      atA = atB;
      b = low + kGolden * (high - low);
      atB = circleSample(environment, e, ring, side, b);
    }
  }
  return atA.distance <= atB.distance ? atA : atB;
}

// The places where `ring`'s circle comes closest to item e: the least of the
// signed distance over the circle in each of its (up to) kMaxDips lowest dips,
// with the item's normal there; how many were found (0 when the item covers no
// point of the circle). A plane's is one, exact (the circle point most against
// its normal). Any other item's distance along the circle can dip in more than
// one place, and the circle touches it in each: a wheel against a step rests on
// the ground below and on the step's edge. The circle is sampled at kSamples
// points and each of the lowest dips searched to its least (golden section over
// the arc about the sample). Each dip's least is a continuous function of the
// ring's position (a dip is born or ends only where two dips merge, at one
// depth), so each contact's depth and energy are continuous: one contact at the
// fixed point of the centre's normal (before) could leave a deeper dip for
// another at once (a vehicle's wheel at a 9 cm ledge: 0.05 J in a step of
// 1e-11 s, a stall), and one contact at the deeper dip swaps between the two, each
// time pressing the ring into the other.
// The dips come in the order of their angle from the lowest point of the circle
// (world -z; -x for a ring lying flat), so that the one a ring rests on keeps its
// name when another dip comes and goes.
constexpr int kMaxDips = 2;
// Only dips that may come within `reach` of the item are searched (a sample
// more than reach + R Δθ above it bounds its dip above reach: the distance
// changes by at most R Δθ / 2 from a sample to the arc's least).
int dipsOnCircle(const Environment& environment, std::int32_t e, const Ring& ring, double reach,
                 CirclePoint (&dips)[kMaxDips]) {
  const auto planes = static_cast<std::int32_t>(environment.planes.size());
  if (e < planes) {
    const GroundPlane& plane = environment.planes[static_cast<std::size_t>(e)];
    dips[0].point = circlePointAgainst(ring, plane.normal);
    return environmentDistance(environment, e, dips[0].point, dips[0].distance, dips[0].normal)
               ? 1
               : 0;
  }
  const Vec3 side = cross(ring.axis, ring.start);
  constexpr int kSamples = 32;
  constexpr double kSpacing = 2.0 * M_PI / kSamples;
  std::array<double, kSamples> sampled{};
  for (int k = 0; k < kSamples; ++k) {
    sampled[k] = circleSample(environment, e, ring, side, kSpacing * k).distance;
  }
  // The lowest samples that are dips: below the sample before and no higher than
  // the one after (a plateau counts once, at its first sample; a circle all at
  // one distance, a ring lying flat, at its first).
  constexpr double kNone = std::numeric_limits<double>::infinity();
  int lowest[kMaxDips] = {-1, -1};
  const auto consider = [&](int k) {
    if (lowest[0] < 0 || sampled[k] < sampled[lowest[0]]) {
      lowest[1] = lowest[0];
      lowest[0] = k;
    } else if (lowest[1] < 0 || sampled[k] < sampled[lowest[1]]) {
      lowest[1] = k;
    }
  };
  for (int k = 0; k < kSamples; ++k) {
    const double here = sampled[k];
    if (here < kNone && here < sampled[(k + kSamples - 1) % kSamples] &&
        here <= sampled[(k + 1) % kSamples])
      consider(k);
  }
  if (lowest[0] < 0 && sampled[0] < kNone &&
      std::all_of(sampled.begin(), sampled.end(), [&](double d) { return d == sampled[0]; }))
    consider(0);
  int count = 0;
  for (const int k : lowest) {
    if (k < 0 || sampled[k] > reach + ring.radius * kSpacing) continue;
    const CirclePoint least =
        leastOnArc(environment, e, ring, side, kSpacing * (k - 1), kSpacing * (k + 1));
    if (least.distance < std::numeric_limits<double>::infinity()) dips[count++] = least;
  }
  // Two searches that ended in one dip (a dip across a plateau): one contact.
  if (count == 2 && norm(dips[0].point - dips[1].point) <= 1e-9 * ring.radius) {
    if (dips[1].distance < dips[0].distance) dips[0] = dips[1];
    count = 1;
  }
  if (count == 2) {
    // The shallower dip's saddle (topological persistence): a dip ends only by
    // merging with the lower of the highs beside it, at that high's distance, so
    // a contact no deeper than its dip lies below that high fades to nothing as
    // the dip ends (and two dips at one depth give the same two depths whichever
    // is the deeper). (The sampled highs: each is continuous in the position.)
    double highs[2] = {-kNone, -kNone};
    for (int arc = 0; arc < 2; ++arc) {
      const int from = lowest[arc], to = lowest[1 - arc];
      for (int k = (from + 1) % kSamples; k != to; k = (k + 1) % kSamples)
        highs[arc] = std::max(highs[arc], sampled[k]);
    }
    const int shallower = dips[1].distance < dips[0].distance ? 0 : 1;
    dips[shallower].saddle = std::max(std::min(highs[0], highs[1]), dips[shallower].distance);
    // Named in the order of their angle from the circle's lowest point.
    const Vec3 up = std::abs(ring.axis.z) > 0.99 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 0.0, 1.0};
    const Vec3 lowestPoint = circlePointAgainst(ring, up);
    const auto fromLowest = [&](const CirclePoint& dip) {
      return norm(dip.point - lowestPoint);  // (the chord: monotone in the angle)
    };
    if (fromLowest(dips[1]) < fromLowest(dips[0])) std::swap(dips[0], dips[1]);
  }
  return count;
}

// A cylinder wheel's two edge circles against every environment item (MODEL §3.1
// with r = 0 on each circle): two contacts, named by the body's first two free
// particles (movable: free, or a rigid tree's), so that a wheel on flat ground carries its load at both edges and a
// tilted one the more at the lower (the line contact's moment).
void cylinderVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                               std::int32_t r, ContactScratch& cache) {
  const Environment& environment = model.environment;
  const RimRing& wheel = model.rims[static_cast<std::size_t>(r)];
  // Edge `side`'s dip k is named by names[side + 2 k].
  std::int32_t names[2 * kMaxDips] = {-1, -1, -1, -1};
  for (std::int32_t k = 0, found = 0; k < wheel.count && found < 2 * kMaxDips; ++k)
    if (cache.tables->movable[wheel.first + k] != 0) names[found++] = wheel.first + k;
  if (names[1] < 0) return;  // a wheel of fewer than two free particles does not roll
  const Vec3 hub = position[wheel.hub];
  const Vec3 along = position[wheel.axisParticle] - hub;
  const double length = norm(along);
  if (!(length > 0.0)) return;
  Ring ring;
  ring.axis = along / length;
  ring.radius = wheel.sphereRadius;
  const Vec3 middle = hub + ring.axis * wheel.axialOffset;
  const Vec3 first = position[wheel.first] - middle;
  const Vec3 inPlane = first - ring.axis * dot(first, ring.axis);
  ring.start = norm(inPlane) > 0.0 ? inPlane / norm(inPlane) : Vec3{1.0, 0.0, 0.0};
  const Vec3 center = rimCenter(model, wheel, position);  // the contact stage's centre
  const double reach = std::hypot(wheel.sphereRadius, wheel.halfLength);
  for (std::int32_t e = 0; e < environment.itemCount(); ++e) {
    if (environmentFarFrom(environment, e, middle, reach, cache.tables->environmentReaches[e]))
      continue;
    ++cache.stats.environmentTests;
    for (int side = 0; side < 2; ++side) {
      ring.center = middle + ring.axis * (side == 0 ? -wheel.halfLength : wheel.halfLength);
      CirclePoint dips[kMaxDips];
      const int count = dipsOnCircle(environment, e, ring, 0.0, dips);
      for (int k = 0; k < count; ++k) {
        if (dips[k].depth(0.0) >= 0.0 || names[side + 2 * k] < 0) continue;
        Contact c;  // carried by the whole body as a rigid round body (a ball's path)
        c.a = names[side + 2 * k];
        c.other = -1 - e;
        c.depth = dips[k].depth(0.0);
        c.normal = dips[k].normal;
        c.rim = r;
        c.arm = dips[k].point - center;  // the contact point on the wheel's own edge
        cache.treeContacts.push_back(c);
      }
    }
  }
}

// A ball's sphere against every environment item (MODEL §3.1 with r = R).
void ballVersusEnvironment(const Model& model, const std::vector<Vec3>& position, std::int32_t r,
                           ContactScratch& cache) {
  const Environment& environment = model.environment;
  const RimRing& ball = model.rims[static_cast<std::size_t>(r)];
  const double radius = ball.sphereRadius;
  const Vec3 center = rimCenter(model, ball, position);
  for (std::int32_t e = 0; e < environment.itemCount(); ++e) {
    if (environmentFarFrom(environment, e, center, radius, cache.tables->environmentReaches[e])) {
      continue;
    }
    ++cache.stats.environmentTests;
    double distance = 0.0;
    Vec3 normal;
    if (!environmentDistance(environment, e, center, distance, normal)) continue;
    // Planes, boxes and spheres: the centre's distance is exact. A heightfield
    // gives the distance to its tangent plane below the query point: take the
    // tangent plane at the contact point c - R n instead, distance(c) =
    // n'·(c - q) + s(q) for the query point q and its distance s(q) and normal n'.
    const auto first = static_cast<std::int32_t>(environment.planes.size());
    if (e >= first && e < first + static_cast<std::int32_t>(environment.heightfields.size())) {
      bool covered = true;
      for (int iteration = 0; iteration < 3 && covered; ++iteration) {
        const Vec3 query = center - normal * radius;
        double at = 0.0;
        Vec3 tangentNormal;
        covered = environmentDistance(environment, e, query, at, tangentNormal);
        if (covered) {
          normal = tangentNormal;
          distance = dot(center - query, normal) + at;
        }
      }
      if (!covered) continue;
    }
    const double depth = distance - radius;
    if (depth >= 0.0) continue;
    Contact c;  // carried by the whole ball, named by its first particle (as a ring)
    c.a = ball.first;
    c.other = -1 - e;
    c.depth = depth;
    c.normal = normal;
    c.rim = r;
    c.arm = normal * -radius;  // on the ball's own surface
    cache.treeContacts.push_back(c);
  }
}

}  // namespace

void rimsVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache) {
  const Environment& environment = model.environment;
  const std::int32_t items = environment.itemCount();
  for (std::size_t r = 0; r < model.rims.size(); ++r) {
    const RimRing& rim = model.rims[r];
    const double tube = model.radius[rim.first];
    bool free = false;
    for (std::int32_t k = 0; k < rim.count && !free; ++k) {
      free = cache.tables->movable[rim.first + k] != 0;  // (a rigid tree's particles move)
    }
    if (!free) continue;
    if (rim.isCylinder()) {
      cylinderVersusEnvironment(model, position, static_cast<std::int32_t>(r), cache);
      continue;
    }
    if (rim.isSphere()) {
      ballVersusEnvironment(model, position, static_cast<std::int32_t>(r), cache);
      continue;
    }
    const Ring ring = ringAt(model, rim, position);
    for (std::int32_t e = 0; e < items; ++e) {
      if (environmentFarFrom(environment, e, ring.center, ring.radius + tube,
                             cache.tables->environmentReaches[e])) {
        continue;
      }
      ++cache.stats.environmentTests;
      CirclePoint dips[kMaxDips];
      const int count = dipsOnCircle(environment, e, ring, tube, dips);
      for (int k = 0; k < count && k < rim.count; ++k) {
        const double depth = dips[k].depth(tube);
        if (depth >= 0.0) continue;
        // The whole ring carries it (contact_force.cpp); its first particle
        // (the second dip's: its second) names it, so the contact keeps its
        // friction anchor as the ring turns.
        Contact c;
        c.a = rim.first + k;
        c.other = -1 - e;
        c.depth = depth;
        c.normal = dips[k].normal;
        c.rim = static_cast<std::int32_t>(r);
        c.arm = dips[k].point - dips[k].normal * tube - ring.center;  // on the torus's own surface
        cache.treeContacts.push_back(c);
      }
    }
  }
}

}  // namespace robophi
