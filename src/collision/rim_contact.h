#pragma once
// Round rims (docs/contact.md): a wheel's ring of particles meets the
// environment through the torus its particles sweep, not through each sphere.

#include <vector>

#include "collision/contact_tables.h"
#include "robophi/model.h"

namespace robophi {

/// Every rim ring of the model against every environment item: appends the
/// touching ones to cache.treeContacts (Contact::rim set, `a` the rim particle
/// nearest to the contact point, `arm` from it to the contact point).
void rimsVersusEnvironment(const Model& model, const std::vector<Vec3>& position,
                           ContactScratch& cache);

}  // namespace robophi
