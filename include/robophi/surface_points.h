#pragma once
// Points of a body's surface mesh (MODEL §3.8, docs/contact.md "Flat faces"):
// where a surface vertex is, and where a vertex or edge contact touches. Defined
// in src/collision/facets.cpp; the contact stage, the sensors and the robotics
// tasks all take a contact's point from here.

#include <cstdint>
#include <vector>

#include "robophi/contact.h"
#include "robophi/model.h"
#include "robophi/vec3.h"

namespace robophi {

/// x_v = Σ w_k p_k of surface vertex `vertex` from `values` (positions or velocities).
Vec3 surfaceVertexPoint(const Model& model, std::int32_t vertex, const std::vector<Vec3>& values);
/// A vertex or edge contact's touching point (c.vertex >= 0): its vertex, or
/// (1 - s) x_vertex + s x_edgeVertex on its edge, from `values`.
Vec3 touchingPoint(const Model& model, const Contact& c, const std::vector<Vec3>& values);

}  // namespace robophi
