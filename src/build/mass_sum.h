#pragma once
// Mass properties accumulated in one frame (the importers' bodies made of several
// links or MJCF bodies): m, Σ m c and Σ (I_c + m (|c|² 1 − c cᵀ)) about the origin.

#include "robophi/multibody.h"
#include "robophi/rotation.h"

namespace robophi::build {

struct MassSum {
  double mass = 0.0;
  Vec3 moment{};
  Mat3 inertiaAtOrigin = Mat3::zero();

  /// Adds a part of mass m (kg) centred at c (m) with its inertia about c (kg·m²).
  void add(double m, const Vec3& c, const Mat3& inertiaAboutCentre) {
    mass += m;
    moment += c * m;
    inertiaAtOrigin = inertiaAtOrigin + inertiaAboutCentre +
                      m * (Mat3::diagonal({dot(c, c), dot(c, c), dot(c, c)}) - outer(c, c));
  }
  /// The sum as one body's mass properties (inertia about its centre of mass).
  BodyMassProperties properties() const {
    BodyMassProperties p;
    p.mass = mass;
    if (mass <= 0.0) return p;
    const Vec3 c = moment / mass;
    p.centerOfMass = c;
    p.inertia =
        inertiaAtOrigin - mass * (Mat3::diagonal({dot(c, c), dot(c, c), dot(c, c)}) - outer(c, c));
    return p;
  }
};

}  // namespace robophi::build
