#pragma once
/// \file
/// Bar calibration (paper experiment 1, docs/robotics.md#bar-calibration-experiment-1):
/// a box lattice's connectors from elastic moduli instead of a spring stiffness.

#include <optional>

#include "robophi/build/objects.h"

namespace robophi::build {

/// Sets the LS (stiffness and damping) and TS of `box`, made by makeBox(spec),
/// from Young's modulus E (Pa, > 0) and the shear modulus G (Pa, > 0; unset:
/// 0.4 E), so that its traction, flexion and torsion stiffness match E·A/L,
/// 3·E·I/L³ and G·J/L (a slender box, calibrated as a beam along its longest
/// side) or the bulk moduli (any other box). Needs cubic cells and G < 0.75 E.
/// Throws SpecError naming "youngModulus", "shearModulus" or "cells" when the
/// lattice cannot be calibrated; `box` is then unchanged.
void calibrateLattice(GeneratedObject& box, const BoxSpec& spec, double youngModulus,
                      std::optional<double> shearModulus = std::nullopt);

}  // namespace robophi::build
