#pragma once
// Round rims and balls (docs/contact.md): a wheel's ring of particles meets the
// environment through the torus its particles sweep, a ball's lattice through
// the sphere of the ball's radius, not through each particle's sphere.

#include <vector>

#include "collision/contact_tables.h"
#include "robophi/model.h"

namespace robophi {

/// The mass centre of a rim's or ball's particles: the point its contacts' arms
/// start from (contact_force.cpp's RingMotion has the same centre with its rates).
Vec3 rimCenter(const Model& model, const RimRing& rim, const std::vector<Vec3>& position);

/// Every rim ring and ball (Model::rims) against every environment item: appends
/// the touching ones to cache.treeContacts (Contact::rim set, `a` the body's
/// first particle, `arm` from its mass centre to the contact point on the body's own surface:
/// docs/contact.md "Where a contact acts").
void rimsVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache);

}  // namespace robophi
