#pragma once
// Round rims and balls (docs/contact.md): a wheel's ring of particles meets the
// environment through the torus its particles sweep, a ball's lattice through
// the sphere of the ball's radius, not through each particle's sphere.

#include <vector>

#include "collision/contact_tables.h"
#include "robophi/model.h"

namespace robophi {

/// Every rim ring and ball (Model::rims) against every environment item: appends
/// the touching ones to cache.treeContacts (Contact::rim set, `a` the body's
/// first particle, `arm` from its mass centre to the contact point).
void rimsVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache);

}  // namespace robophi
