#pragma once
// The contact laws, written once (issue 36; docs/contact.md "The stage"):
// MODEL §3.1's normal force, §3.3's anchor damping and friction laws and §3.7's
// stability rates of one contact, in collision/contact_law.inl over a number
// type. Here they are for doubles and Vec3: the scalar stage
// (contact_force.cpp) and the rigid trees' implicit terms
// (integrate/rigid_trees.cpp) call these; the AVX2 lanes (pair_lanes.cpp)
// include the same source for four contacts at a time.

#include <algorithm>
#include <cmath>

#include "robophi/vec3.h"

namespace robophi::law {

// The operations contact_law.inl asks of its number type, for doubles.
using std::max;
using std::sqrt;
inline double nonNegative(double x) { return x < 0.0 ? 0.0 : x; }

#include "collision/contact_law.inl"  // IWYU pragma: export

using NormalLoad = NormalLoadOf<double>;
using Rates = RatesOf<double>;
using FrictionLoad = FrictionLoadOf<double, Vec3>;

}  // namespace robophi::law
