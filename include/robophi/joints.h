#pragma once
/// \file
/// Reading named joints (MODEL §1: a joint's value is θ for a revolute joint,
/// the slider's distance along its line for a prismatic one).

#include <cstddef>

#include "robophi/model.h"
#include "robophi/state.h"

namespace robophi {

/// The joint's value: rad in [0, 2π) for a revolute joint, m for a prismatic one.
double jointValue(const Model& model, const State& state, std::size_t joint);

/// The joint's rate: rad/s or m/s.
double jointRate(const Model& model, const State& state, std::size_t joint);

}  // namespace robophi
