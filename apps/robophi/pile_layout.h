#pragma once
// The PILE benchmark's geometry, shared by robophi's pile (bench_pile.cpp) and
// the Bullet yardstick (bench/bullet_pile.cpp), so that both drop the same balls
// into the same box: plain numbers, no robophi type.

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace robophi::cli::pile {

constexpr double kRadius = 0.01;     // m
constexpr double kSpacing = 0.025;   // m
constexpr double kDensity = 1000.0;  // kg/m³
constexpr double kLowestCentre = 0.015;  // m above the ground
constexpr double kJitter = 0.002;        // m, the largest per axis
constexpr double kFriction = 0.5;        // μ_s = μ_k between any two surfaces
constexpr double kWallHeight = 0.6, kWallThickness = 0.05;  // m

// SplitMix64: a fixed, portable sequence (std distributions differ between libraries).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [-1, 1).
  double symmetric() { return static_cast<double>(next() >> 11) * 0x1.0p-52 - 1.0; }
};

/// The inner width (m) of the box around n × n × n balls.
inline double width(int n) { return n * kSpacing; }

/// The balls' centres (m): an n × n × n lattice spaced kSpacing, centred on the
/// z axis, the lowest layer at kLowestCentre, each jittered by up to ±kJitter
/// per axis (a fixed seed per n); x fastest, then y, then z.
inline std::vector<std::array<double, 3>> centres(int n) {
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(n) * n * n);
  const double half = 0.5 * width(n);
  SplitMix64 random{0x5EED0000ULL + static_cast<std::uint64_t>(n)};
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const double jx = random.symmetric(), jy = random.symmetric(), jz = random.symmetric();
        out.push_back({-half + (i + 0.5) * kSpacing + jx * kJitter,
                       -half + (j + 0.5) * kSpacing + jy * kJitter,
                       kLowestCentre + k * kSpacing + jz * kJitter});
      }
    }
  }
  return out;
}

/// One of the four walls: its centre and half extents (m).
struct Wall {
  std::array<double, 3> centre, halfExtents;
};

/// The walls standing on the ground around the balls, kWallThickness thick and
/// kWallHeight high, their inner faces at ±width/2 (x walls first).
inline std::array<Wall, 4> walls(int n) {
  const double reach = 0.5 * width(n) + 0.5 * kWallThickness;
  const double halfLength = 0.5 * width(n) + kWallThickness;
  std::array<Wall, 4> out;
  for (int side = 0; side < 4; ++side) {
    const double sign = side % 2 == 0 ? 1.0 : -1.0;
    if (side < 2) {
      out[side] = {{sign * reach, 0.0, 0.5 * kWallHeight},
                   {0.5 * kWallThickness, halfLength, 0.5 * kWallHeight}};
    } else {
      out[side] = {{0.0, sign * reach, 0.5 * kWallHeight},
                   {halfLength, 0.5 * kWallThickness, 0.5 * kWallHeight}};
    }
  }
  return out;
}

/// STEP-SCALING's and SCALING's balls (radius kRadius, mass kScalingMass, no
/// gravity): `count` centres (m) on a cubic lattice of side ⌈∛count⌉ spaced
/// 2 cm from the origin, x fastest, each jittered by up to ±2 mm per axis (a
/// fixed seed): about half the neighbour pairs touch.
constexpr double kScalingMass = 0.004;  // kg
inline std::vector<std::array<double, 3>> scalingCentres(std::int64_t count) {
  std::vector<std::array<double, 3>> out;
  out.reserve(static_cast<std::size_t>(count));
  const auto side = static_cast<std::int64_t>(std::ceil(std::cbrt(static_cast<double>(count))));
  SplitMix64 random{0xC0FFEEULL};
  for (std::int64_t q = 0; q < count; ++q) {
    const auto i = static_cast<double>(q % side);
    const auto j = static_cast<double>((q / side) % side);
    const auto k = static_cast<double>(q / (side * side));
    const double jx = random.symmetric(), jy = random.symmetric(), jz = random.symmetric();
    out.push_back({i * 0.02 + jx * 0.002, j * 0.02 + jy * 0.002, k * 0.02 + jz * 0.002});
  }
  return out;
}

}  // namespace robophi::cli::pile
