#pragma once
// The contact benchmarks: PILE (many spheres falling into a box) and the
// scaling of contact detection with the number of particles.

#include "robophi/scene/scene.h"

namespace robophi::cli {

/// PILE n: M = n³ spheres of radius 1 cm, density 1000 kg/m³, each its own
/// object, on a cubic lattice spaced 2.5 cm (lowest centres at z = 1.5 cm),
/// jittered by up to ±2 mm (fixed seed), inside a square box of inner width
/// n·2.5 cm with walls 0.6 m high, on the ground; friction 0.5; 1 s with the
/// constant-step symplectic Euler. κ_c and δ: see docs/contact.md (PILE).
Scene makePileScene(int n);

/// Times one contact-detection pass on piles of 1e3 .. 1e6 particles (single
/// particles in the grid, and one object of unconnected particles searched
/// with its sphere tree), prints the times and the log-log slopes. Returns 0.
int runContactScaling(bool json);

/// Times whole steps per particle from 1e3 to 1e6 particles (the CLOTH scene,
/// and single balls in contact) on up to `threads` threads (0: the cores
/// available), prints the costs and the spread highest / lowest. Returns 0.
int runStepScaling(bool json, int threads);

}  // namespace robophi::cli
