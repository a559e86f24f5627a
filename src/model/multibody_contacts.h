#pragma once
// Contact loads taken implicitly in a rigid tree's step (docs/model.md §7
// "Contacts on rigid trees"): the contact stage's force on a tree body stays as
// it found it, and the step adds the change of that force over the step,
// linearised, to its implicit solve.

#include <cstdint>
#include <vector>

#include "robophi/multibody.h"

namespace robophi {

/// The stiffness and damping of a contact's load on a point of a tree body: over
/// the step the load changes by −K δp − C δv, K = k_n n nᵀ + k_t (I − n nᵀ) and C
/// alike, δp and δv the point's displacement and change of velocity. k_t and c_t
/// are 0 for a contact that slides.
struct PointLoadStiffness {
  std::int32_t body = -1;
  Vec3 point;   // p_WP (m), in W
  Vec3 normal;  // unit
  double normalStiffness = 0.0, normalDamping = 0.0;
  double tangentialStiffness = 0.0, tangentialDamping = 0.0;
};

/// stepMultibody (multibody.h) with the loads' stiffness and damping implicit:
/// (M + dt (B + Σ Jᵀ C J) + dt² (K + Σ Jᵀ K J)) Δv = ..., J each point's
/// Jacobian. The scheme's loss ½ dt² v⁺ᵀ Jᵀ K J v⁺ + dt v⁺ᵀ Jᵀ C J Δv is booked
/// as dissipated, and a free tree's momentum takes the loads' change.
MultibodyStepReport stepMultibody(const Multibody& multibody, std::vector<double>& q,
                                  std::vector<double>& v, const MultibodyInputs& inputs,
                                  const std::vector<PointLoadStiffness>& implicitLoads, double dt,
                                  const Vec3& gravity, MultibodyWorkspace& workspace);

}  // namespace robophi
