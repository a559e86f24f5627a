// Round rims: the closest point of a ring's circle to an environment item, found
// by a fixed point (the circle point whose direction from the centre is the
// item's inward normal projected on the ring plane: exact for a plane, a few
// iterations for a curved or stepped surface), then the torus of the particles'
// radius around it (MODEL §3.1 depth d = distance - r).
#include "collision/rim_contact.h"

#include <cmath>

#include "collision/environment.h"

namespace robophi {

namespace {

struct Ring {
  Vec3 center, axis, start;  // start: unit direction to the ring's first particle
  double radius = 0.0;
};

Ring ringAt(const Model& model, const RimRing& rim, const std::vector<Vec3>& p) {
  Ring ring;
  // The mass centre of the ring's particles (contact_force.cpp RingMotion).
  double mass = 0.0;
  for (std::int32_t k = 0; k < rim.count; ++k) {
    ring.center += p[rim.first + k] * model.mass[rim.first + k];
    mass += model.mass[rim.first + k];
  }
  ring.center = ring.center / mass;
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
      free = model.inverseMass[rim.first + k] != 0.0;
    }
    if (!free) continue;
    const Ring ring = ringAt(model, rim, position);
    for (std::int32_t e = 0; e < items; ++e) {
      if (environmentFarFrom(environment, e, ring.center, ring.radius + tube,
                             cache.tables->environmentTops[e])) {
        continue;
      }
      ++cache.stats.environmentTests;
      double distance = 0.0;
      Vec3 normal;
      if (!environmentDistance(environment, e, ring.center, distance, normal)) continue;
      Vec3 point = circlePointAgainst(ring, normal);
      bool reaches = true;
      for (int iteration = 0; iteration < 3 && reaches; ++iteration) {
        reaches = environmentDistance(environment, e, point, distance, normal);
        if (reaches) point = circlePointAgainst(ring, normal);
      }
      if (!reaches || !environmentDistance(environment, e, point, distance, normal)) continue;
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
      c.arm = point - normal * (tube + depth) - ring.center;
      cache.treeContacts.push_back(c);
    }
  }
}

}  // namespace robophi
