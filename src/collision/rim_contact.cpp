// Round rims: the closest point of a ring's circle to an environment item, found
// by a fixed point (the circle point whose direction from the centre is the
// item's inward normal projected on the ring plane: exact for a plane, a few
// iterations for a curved or stepped surface), then the torus of the particles'
// radius around it (MODEL §3.1 depth d = distance - r).
// Cylinder wheels (an imported robot's): the two edge circles of the cylinder
// about the axis its hub and axis particles give, each as a ring of tube 0.
// Round balls: the sphere of the ball's radius R about its particles' mass
// centre, d = distance(item, centre) - R, the contact point -n R from it.
// On a heightfield the distance is to the tangent plane at the contact point
// (a fixed point from the tangent plane below the centre), as a ring's.
#include "collision/rim_contact.h"

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

// The fixed point above from `normal`: the circle point, its signed distance to
// item e and the item's normal there; false if the item does not cover it.
bool fixedPointOnCircle(const Environment& environment, std::int32_t e, const Ring& ring,
                        Vec3 normal, Vec3& point, double& distance, Vec3& outNormal) {
  point = circlePointAgainst(ring, normal);
  for (int iteration = 0; iteration < 3; ++iteration) {
    if (!environmentDistance(environment, e, point, distance, normal)) return false;
    point = circlePointAgainst(ring, normal);
  }
  return environmentDistance(environment, e, point, distance, outNormal);
}

// Near a box's faces and edges, or a heightfield's sides, the fixed point from
// the centre's normal can settle on one face while the circle is deeper in
// another (a wheel lying against a ramp's side, one rolling off a terrain's
// edge). (Inside a heightfield's rectangle its surface is smooth: not there.)
bool nearFeatures(const Environment& environment, std::int32_t e, const Ring& ring) {
  const auto planes = static_cast<std::int32_t>(environment.planes.size());
  const auto fields = static_cast<std::int32_t>(environment.heightfields.size());
  const auto boxes = static_cast<std::int32_t>(environment.boxes.size());
  if (e < planes || e >= planes + fields + boxes) return false;
  if (e >= planes + fields) return true;
  const Heightfield& field = environment.heightfields[static_cast<std::size_t>(e - planes)];
  const double reach = ring.radius;
  return ring.center.x - reach < field.originX ||
         ring.center.x + reach > field.originX + (field.columns - 1) * field.cellSizeX ||
         ring.center.y - reach < field.originY ||
         ring.center.y + reach > field.originY + (field.rows - 1) * field.cellSizeY;
}

// The point of `ring`'s circle closest to item e, by the fixed point above, with
// its signed distance and the item's normal there; false if the item does not
// cover it. Near a box or a heightfield's side, also eight points around the
// circle: when one is deeper, the fixed point from there, and the deepest point
// found.
bool closestOnCircle(const Environment& environment, std::int32_t e, const Ring& ring, Vec3& point,
                     double& distance, Vec3& normal) {
  Vec3 start;
  bool found = environmentDistance(environment, e, ring.center, distance, start) &&
               fixedPointOnCircle(environment, e, ring, start, point, distance, normal);
  if (!nearFeatures(environment, e, ring)) return found;
  const Vec3 side = cross(ring.axis, ring.start);
  constexpr int kSamples = 8;
  double deepest = found ? distance - 1e-9 * ring.radius : std::numeric_limits<double>::infinity();
  Vec3 deepestPoint, deepestNormal;
  bool sampled = false;
  for (int k = 0; k < kSamples; ++k) {
    const double angle = 2.0 * M_PI * k / kSamples;
    const Vec3 at = ring.center + (ring.start * std::cos(angle) + side * std::sin(angle)) * ring.radius;
    double d = 0.0;
    Vec3 n;
    if (!environmentDistance(environment, e, at, d, n) || !(d < deepest)) continue;
    deepest = d;
    deepestPoint = at;
    deepestNormal = n;
    sampled = true;
  }
  if (!sampled) return found;
  Vec3 refined, refinedNormal;
  double refinedDistance = 0.0;
  if (fixedPointOnCircle(environment, e, ring, deepestNormal, refined, refinedDistance,
                         refinedNormal) &&
      refinedDistance < deepest) {
    deepestPoint = refined;
    deepest = refinedDistance;
    deepestNormal = refinedNormal;
  }
  point = deepestPoint;
  distance = deepest;
  normal = deepestNormal;
  return true;
}

// A cylinder wheel's two edge circles against every environment item (MODEL §3.1
// with r = 0 on each circle): two contacts, named by the body's first two free
// particles (movable: free, or a rigid tree's), so that a wheel on flat ground carries its load at both edges and a
// tilted one the more at the lower (the line contact's moment).
void cylinderVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                               std::int32_t r, ContactScratch& cache) {
  const Environment& environment = model.environment;
  const RimRing& wheel = model.rims[static_cast<std::size_t>(r)];
  std::int32_t names[2] = {-1, -1};
  for (std::int32_t k = 0, found = 0; k < wheel.count && found < 2; ++k)
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
    if (environmentFarFrom(environment, e, middle, reach, cache.tables->environmentTops[e]))
      continue;
    ++cache.stats.environmentTests;
    for (int side = 0; side < 2; ++side) {
      ring.center = middle + ring.axis * (side == 0 ? -wheel.halfLength : wheel.halfLength);
      Vec3 point, normal;
      double depth = 0.0;
      if (!closestOnCircle(environment, e, ring, point, depth, normal) || depth >= 0.0) continue;
      Contact c;  // carried by the whole body as a rigid round body (a ball's path)
      c.a = names[side];
      c.other = -1 - e;
      c.depth = depth;
      c.normal = normal;
      c.rim = r;
      c.arm = point - center;  // the contact point on the wheel's own edge
      cache.treeContacts.push_back(c);
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
    if (environmentFarFrom(environment, e, center, radius, cache.tables->environmentTops[e])) {
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
                             cache.tables->environmentTops[e])) {
        continue;
      }
      ++cache.stats.environmentTests;
      double distance = 0.0;
      Vec3 point, normal;
      if (!closestOnCircle(environment, e, ring, point, distance, normal)) continue;
      const double depth = distance - tube;
      if (depth >= 0.0) continue;
      // The whole ring carries it (contact_force.cpp); its first particle
      // names it, so the contact keeps its friction anchor as the ring turns.
      Contact c;
      c.a = rim.first;
      c.other = -1 - e;
      c.depth = depth;
      c.normal = normal;
      c.rim = static_cast<std::int32_t>(r);
      c.arm = point - normal * tube - ring.center;  // on the torus's own surface
      cache.treeContacts.push_back(c);
    }
  }
}

}  // namespace robophi
