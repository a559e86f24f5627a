// External viscosity (MODEL §3.4): F_v = -k (V·n) V̂ if V·n >= 0, else 0, with n
// the outward surface normal at the particle, estimated as the direction from
// its object's centre of mass to the particle. A particle alone in its object
// (or at that centre) is all surface: n = V̂, so F_v = -k V.
#include <cmath>

#include "collision/contact_stage.h"

namespace robophi {

double accumulateViscosity(const Model& model, const std::vector<Vec3>& position,
                           const std::vector<Vec3>& velocity, std::vector<Vec3>& force,
                           ContactScratch& cache) {
  const double k = model.environment.viscosity;
  if (!(k > 0.0)) return 0.0;
  const ParticleIndex n = model.particleCount();
  const std::size_t objects = model.objects.size();
  cache.objectCentroid.assign(objects, Vec3{});
  cache.objectMass.assign(objects, 0.0);
  for (ParticleIndex i = 0; i < n; ++i) {
    const std::int32_t o = cache.tables->particleObject[i];
    if (o < 0) continue;
    cache.objectCentroid[o] += position[i] * model.mass[i];
    cache.objectMass[o] += model.mass[i];
  }
  for (std::size_t o = 0; o < objects; ++o) {
    if (cache.objectMass[o] > 0.0)
      cache.objectCentroid[o] = cache.objectCentroid[o] / cache.objectMass[o];
  }
  double power = 0.0;
  for (ParticleIndex i = 0; i < n; ++i) {
    if (model.inverseMass[i] == 0.0) continue;
    const Vec3& v = velocity[i];
    const double speed = norm(v);
    if (!(speed > 0.0)) continue;
    const Vec3 direction = v / speed;
    double facing = speed;  // V·n with n = V̂
    const std::int32_t o = cache.tables->particleObject[i];
    if (o >= 0 && model.objects[o].particleCount > 1) {
      const Vec3 offset = position[i] - cache.objectCentroid[o];
      const double length = norm(offset);
      if (length > 0.0) facing = dot(v, offset) / length;
    }
    if (facing <= 0.0) continue;
    force[i] -= direction * (k * facing);
    power -= k * facing * speed;
  }
  return power;
}

}  // namespace robophi
