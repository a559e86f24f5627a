#include "robophi/build/objects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "build/checks.h"

namespace robophi::build {

namespace {

// θ = atan2(|u × w|, u·w), MODEL §1 TS.
double angleAt(const Vec3& pA, const Vec3& pC, const Vec3& pB) {
  const Vec3 u = pA - pC, w = pB - pC;
  return std::atan2(norm(cross(u, w)), dot(u, w));
}

void addBend(GeneratedObject& object, int a, int c, int b) {
  const auto& p = object.position;
  object.torsionSprings.push_back(TorsionSpring{a, c, b, angleAt(p[a], p[c], p[b]), 0.0, 0.0});
}

void addParticles(GeneratedObject& object, std::vector<Vec3> positions, double totalMass,
                  double particleRadius) {
  const auto count = static_cast<double>(positions.size());
  object.position = std::move(positions);
  object.mass.assign(object.size(), totalMass / count);
  object.radius.assign(object.size(), particleRadius);
}

// A lattice of n[0]×n[1]×n[2] cells; index[(i n1 + j) n2 + k] is the particle
// at cell (i, j, k), or -1 where a shape (the ball) leaves the cell empty.
struct Lattice {
  std::array<int, 3> n{1, 1, 1};
  std::vector<int> index;

  int at(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) return -1;
    return index[static_cast<std::size_t>((i * n[1] + j) * n[2] + k)];
  }
};

// Cell centres of a lattice filling `size` around `center` (inset by half a
// cell), keeping the cells `keep` accepts.
template <typename Keep>
Lattice fillLattice(std::array<int, 3> n, const Vec3& center, const Vec3& size,
                    std::vector<Vec3>& positions, Keep keep) {
  Lattice lattice{n, {}};
  const Vec3 cell{size.x / n[0], size.y / n[1], size.z / n[2]};
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        const Vec3 offset{(i + 0.5) * cell.x - 0.5 * size.x, (j + 0.5) * cell.y - 0.5 * size.y,
                          (k + 0.5) * cell.z - 0.5 * size.z};
        if (keep(offset)) {
          lattice.index.push_back(static_cast<int>(positions.size()));
          positions.push_back(center + offset);
        } else {
          lattice.index.push_back(-1);
        }
      }
    }
  }
  return lattice;
}

// LS to the 26 neighbours (axis, face and body diagonals; each pair once) and
// TS along each lattice line.
void connectLattice(GeneratedObject& object, const Lattice& lattice) {
  const auto& n = lattice.n;
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        const int self = lattice.at(i, j, k);
        if (self < 0) continue;
        for (int di = -1; di <= 1; ++di) {
          for (int dj = -1; dj <= 1; ++dj) {
            for (int dk = -1; dk <= 1; ++dk) {
              // Only the 13 offsets whose first non-zero component is positive.
              const bool forward = di > 0 || (di == 0 && (dj > 0 || (dj == 0 && dk > 0)));
              const int other = lattice.at(i + di, j + dj, k + dk);
              if (forward && other >= 0) addLink(object, self, other);
            }
          }
        }
        const int along[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (const auto& e : along) {
          const int before = lattice.at(i - e[0], j - e[1], k - e[2]);
          const int after = lattice.at(i + e[0], j + e[1], k + e[2]);
          if (before >= 0 && after >= 0) addBend(object, before, self, after);
        }
      }
    }
  }
}

// MODEL §3.8: a surface mesh for a lattice of cells n (particles at cell
// centres). Vertices sit on the cell-corner grid of the true outer faces; an axis
// with one cell holds a sheet at mid-thickness (half thickness `sheetRadius`).
// Each vertex is embedded in the 2×2×2 (or 2×2) block of particles nearest to
// it by affine least-squares weights w_k = 1/N + Σ_a (u_a − ū_a) D_ka / M_aa
// (D_k the particle's offset from the block's mean ū in cells, M = Σ D Dᵀ,
// diagonal for a block): exact for any affine motion of the block, so rigid
// motions carry the surface exactly, and Σ w_k = 1.
void addLatticeSurface(GeneratedObject& object, const Lattice& lattice, double sheetRadius) {
  const auto& n = lattice.n;
  int sheetAxis = -1, sheets = 0;
  for (int a = 0; a < 3; ++a) {
    if (n[a] == 1) {
      sheetAxis = a;
      ++sheets;
    }
  }
  if (sheets > 1) return;  // a rod or a single particle: no surface
  std::array<int, 3> m{};  // vertex grid size per axis
  for (int a = 0; a < 3; ++a) m[a] = a == sheetAxis ? 1 : n[a] + 1;
  std::vector<int> vertexAt(static_cast<std::size_t>(m[0] * m[1] * m[2]), -1);
  const auto gridIndex = [&](int a, int b, int c) { return (a * m[1] + b) * m[2] + c; };
  const auto onSurface = [&](const std::array<int, 3>& g) {
    if (sheetAxis >= 0) return true;
    for (int a = 0; a < 3; ++a)
      if (g[a] == 0 || g[a] == n[a]) return true;
    return false;
  };
  std::vector<Vec3> rest;  // vertex positions at build, for the triangles' orientation
  for (int a = 0; a < m[0]; ++a) {
    for (int b = 0; b < m[1]; ++b) {
      for (int c = 0; c < m[2]; ++c) {
        const std::array<int, 3> g{a, b, c};
        if (!onSurface(g)) continue;
        std::array<double, 3> u{};  // position in cells
        std::array<std::array<int, 2>, 3> block{};
        std::array<int, 3> blockSize{};
        for (int k = 0; k < 3; ++k) {
          if (k == sheetAxis) {
            u[k] = 0.5;
            block[k] = {0, 0};
            blockSize[k] = 1;
          } else {
            u[k] = g[k];
            const int lo = std::clamp(static_cast<int>(std::floor(u[k] - 0.5)), 0, n[k] - 2);
            block[k] = {lo, lo + 1};
            blockSize[k] = 2;
          }
        }
        SurfaceVertex vertex;
        const int count = blockSize[0] * blockSize[1] * blockSize[2];
        int slot = 0;
        Vec3 x;
        for (int i = 0; i < blockSize[0]; ++i) {
          for (int j = 0; j < blockSize[1]; ++j) {
            for (int k = 0; k < blockSize[2]; ++k) {
              const std::array<int, 3> cell{block[0][i], block[1][j], block[2][k]};
              double w = 1.0 / count;
              for (int axis = 0; axis < 3; ++axis) {
                if (blockSize[axis] < 2) continue;
                const double mean = block[axis][0] + 1.0;       // (lo + 0.5 + lo + 1.5) / 2
                const double offset = cell[axis] + 0.5 - mean;  // ±0.5
                w += (u[axis] - mean) * offset / (count * 0.25);
              }
              const int particle = lattice.at(cell[0], cell[1], cell[2]);
              vertex.particle[slot] = particle;
              vertex.weight[slot] = w;
              x += object.position[particle] * w;
              ++slot;
            }
          }
        }
        vertexAt[gridIndex(a, b, c)] = static_cast<int>(object.surfaceVertices.size());
        object.surfaceVertices.push_back(vertex);
        rest.push_back(x);
      }
    }
  }
  Vec3 center;
  for (const Vec3& p : object.position) center += p / static_cast<double>(object.size());
  // Two triangles per boundary cell of each face, wound outwards.
  const auto addQuad = [&](int v0, int v1, int v2, int v3, const Vec3& outward) {
    for (const std::array<int, 3> t : {std::array<int, 3>{v0, v1, v2}, {v0, v2, v3}}) {
      SurfaceTriangle triangle{{t[0], t[1], t[2]}, -1};
      const Vec3 normal = cross(rest[t[1]] - rest[t[0]], rest[t[2]] - rest[t[0]]);
      if (dot(normal, outward) < 0.0) std::swap(triangle.vertex[1], triangle.vertex[2]);
      object.surfaceTriangles.push_back(triangle);
    }
  };
  for (int axis = 0; axis < 3; ++axis) {
    if (sheetAxis >= 0 && axis != sheetAxis) continue;
    const int e1 = (axis + 1) % 3, e2 = (axis + 2) % 3;
    const std::array<int, 2> sides =
        axis == sheetAxis ? std::array<int, 2>{0, -1} : std::array<int, 2>{0, n[axis]};
    for (const int side : sides) {
      if (side < 0) continue;
      for (int i = 0; i < m[e1] - 1; ++i) {
        for (int j = 0; j < m[e2] - 1; ++j) {
          const auto at = [&](int di, int dj) {
            std::array<int, 3> g{};
            g[axis] = side;
            g[e1] = i + di;
            g[e2] = j + dj;
            return vertexAt[gridIndex(g[0], g[1], g[2])];
          };
          Vec3 outward = rest[at(0, 0)] - center;
          if (axis != sheetAxis) {
            const Vec3 face = (rest[at(0, 0)] + rest[at(1, 1)]) * 0.5 - center;
            const double axisComponent[3] = {face.x, face.y, face.z};
            outward = Vec3{};
            (axis == 0   ? outward.x
             : axis == 1 ? outward.y
                         : outward.z) = axisComponent[axis] >= 0.0 ? 1.0 : -1.0;
          }
          addQuad(at(0, 0), at(1, 0), at(1, 1), at(0, 1), outward);
        }
      }
    }
  }
  object.surfaceRadius = sheetAxis >= 0 ? sheetRadius : 0.0;
}

// Rodrigues: R v = v cos φ + (k × v) sin φ + k (k·v)(1 - cos φ), k a unit axis.
Vec3 rotate(const Vec3& v, const Vec3& unitAxis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + cross(unitAxis, v) * s + unitAxis * (dot(unitAxis, v) * (1.0 - c));
}

// Two unit vectors perpendicular to the unit vector `n` and to each other.
void basisAround(const Vec3& n, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::fabs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  e1 = cross(n, helper);
  e1 = e1 / norm(e1);
  e2 = cross(n, e1);
}

// The LS and TS connectLattice makes on a full n[0]×n[1]×n[2] lattice (as doubles:
// the counts may be far beyond int): one LS per pair of neighbours among the 13
// forward offsets, one TS per particle with both neighbours along an axis.
double latticeConnectors(const std::array<double, 3>& n) {
  double count = 0.0;
  for (int di = -1; di <= 1; ++di)
    for (int dj = -1; dj <= 1; ++dj)
      for (int dk = -1; dk <= 1; ++dk)
        if (di > 0 || (di == 0 && (dj > 0 || (dj == 0 && dk > 0))))
          count += std::max(0.0, n[0] - std::abs(di)) * std::max(0.0, n[1] - std::abs(dj)) *
                   std::max(0.0, n[2] - std::abs(dk));
  for (int axis = 0; axis < 3; ++axis)
    count += std::max(0.0, n[axis] - 2.0) * n[(axis + 1) % 3] * n[(axis + 2) % 3];
  return count;
}

// A lattice's cells: each count >= 1, and its particles and connectors within the
// budget (checked before anything is allocated).
template <std::size_t N>
void checkCells(const char* spec, const std::array<int, N>& cells) {
  std::array<double, 3> n{1.0, 1.0, 1.0};
  std::string text;
  for (std::size_t i = 0; i < N; ++i) {
    check::atLeast(spec, "cells", cells[i], 1);
    n[i] = cells[i];
    text += (i == 0 ? "" : "×") + std::to_string(cells[i]);
  }
  check::fitsBudget(spec, "cells", "'cells' " + text, n[0] * n[1] * n[2], latticeConnectors(n));
}

}  // namespace

int addParticle(GeneratedObject& object, const Vec3& position, double mass, double radius) {
  object.position.push_back(position);
  object.mass.push_back(mass);
  object.radius.push_back(radius);
  if (!object.fixed.empty()) object.fixed.push_back(false);
  return static_cast<int>(object.position.size()) - 1;
}

int addLink(GeneratedObject& object, int a, int b) {
  const double restLength = norm(object.position[a] - object.position[b]);
  object.linearSprings.push_back(LinearSpring{a, b, restLength, 0.0, 0.0});
  return static_cast<int>(object.linearSprings.size()) - 1;
}

GeneratedObject makeRope(const RopeSpec& spec) {
  constexpr const char* kSpec = "RopeSpec";
  check::finite(kSpec, "start", spec.start, "m");
  check::finite(kSpec, "end", spec.end, "m");
  if (!(norm(spec.end - spec.start) > 0.0))
    check::fail(kSpec, "end", "'end' equals 'start': the rope's links would have rest length 0");
  check::atLeast(kSpec, "particles", spec.particles, 2);
  check::fitsBudget(kSpec, "particles", "'particles' " + std::to_string(spec.particles),
                    spec.particles, 2.0 * spec.particles - 3.0);
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::nonNegative(kSpec, "radius", spec.radius, "m");
  GeneratedObject rope;
  const int n = spec.particles;
  std::vector<Vec3> positions;
  for (int i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.5 : static_cast<double>(i) / (n - 1);
    positions.push_back(spec.start + (spec.end - spec.start) * t);
  }
  rope.spacing = n > 1 ? norm(spec.end - spec.start) / (n - 1) : 0.0;
  addParticles(rope, std::move(positions), spec.mass,
               spec.radius > 0.0 ? spec.radius : 0.5 * rope.spacing);
  for (int i = 0; i + 1 < n; ++i) addLink(rope, i, i + 1);
  for (int i = 1; i + 1 < n; ++i) addBend(rope, i - 1, i, i + 1);
  // Its links slide one by one (each particle's friction decides alone) and
  // carry no contact moment (they do not turn).
  rope.contact.frictionPerParticle = true;
  rope.contact.turns = false;
  return rope;
}

GeneratedObject makeBox(const BoxSpec& spec) {
  constexpr const char* kSpec = "BoxSpec";
  check::finite(kSpec, "center", spec.center, "m");
  check::positiveEach(kSpec, "size", spec.size, "m");
  checkCells(kSpec, spec.cells);
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::nonNegative(kSpec, "radius", spec.radius, "m");
  GeneratedObject box;
  std::vector<Vec3> positions;
  const Lattice lattice =
      fillLattice(spec.cells, spec.center, spec.size, positions, [](const Vec3&) { return true; });
  const double cellMin = std::min(
      {spec.size.x / spec.cells[0], spec.size.y / spec.cells[1], spec.size.z / spec.cells[2]});
  box.spacing = cellMin;
  addParticles(box, std::move(positions), spec.mass,
               spec.radius > 0.0 ? spec.radius : 0.5 * cellMin);
  connectLattice(box, lattice);
  if (spec.facets) {
    const double sizes[3] = {spec.size.x, spec.size.y, spec.size.z};
    double sheet = 0.0;
    for (int a = 0; a < 3; ++a)
      if (spec.cells[a] == 1) sheet = 0.5 * sizes[a];
    addLatticeSurface(box, lattice, sheet);
  }
  return box;
}

GeneratedObject makePlate(const PlateSpec& spec) {
  constexpr const char* kSpec = "PlateSpec";
  check::finite(kSpec, "center", spec.center, "m");
  if (!(spec.sizeX > 0.0 && spec.sizeY > 0.0) || !std::isfinite(spec.sizeX + spec.sizeY))
    check::fail(kSpec, "size",
                "'size' must be > 0 m in each direction, got [" + check::number(spec.sizeX) + ", " +
                    check::number(spec.sizeY) + "]");
  check::nonNegative(kSpec, "thickness", spec.thickness, "m");
  checkCells(kSpec, spec.cells);
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::nonNegative(kSpec, "radius", spec.radius, "m");
  GeneratedObject plate;
  std::vector<Vec3> positions;
  const Vec3 size{spec.sizeX, spec.sizeY, 0.0};
  const Lattice lattice = fillLattice({spec.cells[0], spec.cells[1], 1}, spec.center, size,
                                      positions, [](const Vec3&) { return true; });
  const double cellMin = std::min(spec.sizeX / spec.cells[0], spec.sizeY / spec.cells[1]);
  const double thickness = spec.thickness > 0.0 ? spec.thickness : cellMin;
  plate.spacing = cellMin;
  addParticles(plate, std::move(positions), spec.mass,
               spec.radius > 0.0 ? spec.radius : 0.5 * std::min(cellMin, thickness));
  connectLattice(plate, lattice);
  if (spec.facets) addLatticeSurface(plate, lattice, 0.5 * thickness);
  return plate;
}

GeneratedObject makeBall(const BallSpec& spec) {
  constexpr const char* kSpec = "BallSpec";
  check::finite(kSpec, "center", spec.center, "m");
  check::positive(kSpec, "radius", spec.radius, "m");
  check::atLeast(kSpec, "cells", spec.cells, 1);
  check::atMost(kSpec, "cells", spec.cells, 400);
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::nonNegative(kSpec, "particleRadius", spec.particleRadius, "m");
  GeneratedObject ball;
  const int n = spec.cells;
  const double diameter = 2.0 * spec.radius;
  const double cell = diameter / n;
  // Keep the cells whose centre is inside the ball (with a rounding margin).
  const double limit = spec.radius * (1.0 + 1e-9);
  // The budget before allocating: about π/6 n³ particles, each with at most 13 LS and 3 TS.
  const double cube = static_cast<double>(n) * n * n;
  check::fitsBudget(kSpec, "cells", "'cells' " + std::to_string(n), std::numbers::pi / 6.0 * cube,
                    16.0 * std::numbers::pi / 6.0 * cube);
  std::vector<Vec3> positions;
  const Lattice lattice =
      fillLattice({n, n, n}, spec.center, {diameter, diameter, diameter}, positions,
                  [&](const Vec3& offset) { return norm(offset) <= limit; });
  ball.spacing = cell;
  const double defaultRadius = n == 1 ? spec.radius : 0.5 * cell;
  addParticles(ball, std::move(positions), spec.mass,
               spec.particleRadius > 0.0 ? spec.particleRadius : defaultRadius);
  connectLattice(ball, lattice);
  // MODEL §3.1 round balls: the lattice (symmetric about the centre, so its mass
  // centre is the ball's) meets the environment as the sphere of the ball's radius.
  const auto count = static_cast<std::int32_t>(ball.size());
  if (spec.round && count > 1) ball.rims.push_back(RimRing{0, count, kNoParticle, spec.radius});
  return ball;
}

GeneratedObject makeWheel(const WheelSpec& spec) {
  constexpr const char* kSpec = "WheelSpec";
  check::finite(kSpec, "center", spec.center, "m");
  check::positive(kSpec, "radius", spec.radius, "m");
  check::positive(kSpec, "width", spec.width, "m");
  check::nonZero(kSpec, "axis", spec.axis);
  check::atLeast(kSpec, "rimParticles", spec.rimParticles, 3);
  check::fitsBudget(kSpec, "rimParticles", "'rimParticles' " + std::to_string(spec.rimParticles),
                    2.0 * spec.rimParticles + 2.0, 9.0 * spec.rimParticles + 1.0);
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::nonNegative(kSpec, "hubSpan", spec.hubSpan, "m");
  GeneratedObject wheel;
  const int n = spec.rimParticles;
  const Vec3 axis = spec.axis / norm(spec.axis);
  Vec3 e1, e2;
  basisAround(axis, e1, e2);
  // Two rings across the width: cells of width/2, particles at ±width/4.
  const double halfGap = 0.25 * spec.width;
  const double particleRadius = std::min(0.25 * spec.width, spec.radius * std::sin(M_PI / n));
  const double rimRadius = spec.radius - particleRadius;
  std::vector<Vec3> positions;
  for (int ring = 0; ring < 2; ++ring) {
    const Vec3 side = axis * (ring == 0 ? -halfGap : halfGap);
    for (int i = 0; i < n; ++i) {
      const double phi = 2.0 * M_PI * i / n;
      positions.push_back(spec.center + side +
                          (e1 * std::cos(phi) + e2 * std::sin(phi)) * rimRadius);
    }
  }
  const int hub0 = 2 * n, hub1 = 2 * n + 1;
  const double hubHalfSpan = spec.hubSpan > 0.0 ? 0.5 * spec.hubSpan : halfGap;
  positions.push_back(spec.center - axis * hubHalfSpan);
  positions.push_back(spec.center + axis * hubHalfSpan);
  wheel.spacing = std::min(2.0 * halfGap, 2.0 * rimRadius * std::sin(M_PI / n));
  addParticles(wheel, std::move(positions), spec.mass, particleRadius);
  for (int i = 0; i < n; ++i) {
    const int next = (i + 1) % n;
    const int a0 = i, b0 = next, a1 = n + i, b1 = n + next;
    addLink(wheel, a0, b0);  // rim, ring 0
    addLink(wheel, a1, b1);  // rim, ring 1
    addLink(wheel, a0, a1);  // across the width
    addLink(wheel, a0, b1);  // diagonals: the rim band is triangulated
    addLink(wheel, b0, a1);
    // Spokes to both hub particles: each rim particle is held in 3-D.
    addLink(wheel, a0, hub0);
    addLink(wheel, a0, hub1);
    addLink(wheel, a1, hub0);
    addLink(wheel, a1, hub1);
  }
  addLink(wheel, hub0, hub1);  // axle
  // The rings meet the environment through their round surface (docs/contact.md).
  wheel.rims.push_back(RimRing{0, n, hub0});
  wheel.rims.push_back(RimRing{n, n, hub1});
  return wheel;
}

void rotateObject(GeneratedObject& object, const Vec3& pivot, const Vec3& axis, double angle) {
  check::finite("rotateObject", "pivot", pivot, "m");
  check::nonZero("rotateObject", "axis", axis);
  check::finite("rotateObject", "angle", angle, "rad");
  if (angle == 0.0) return;
  const Vec3 unitAxis = axis / norm(axis);
  for (auto& p : object.position) p = pivot + rotate(p - pivot, unitAxis, angle);
}

void rotateObjectRpy(GeneratedObject& object, const Vec3& pivot, const Vec3& rollPitchYaw) {
  check::finite("rotateObjectRpy", "rpy", rollPitchYaw, "rad");
  // R = Rz(yaw) Ry(pitch) Rx(roll): roll first, about the fixed axes.
  rotateObject(object, pivot, {1, 0, 0}, rollPitchYaw.x);
  rotateObject(object, pivot, {0, 1, 0}, rollPitchYaw.y);
  rotateObject(object, pivot, {0, 0, 1}, rollPitchYaw.z);
}

double defaultStiffness(const GeneratedObject& object, double naturalFrequency) {
  check::positive("defaultStiffness", "naturalFrequency", naturalFrequency, "rad/s");
  // Σ over the springs at particle i of (1/m_i + 1/m_j), per unit stiffness.
  std::vector<double> rowSum(object.size(), 0.0);
  for (const auto& s : object.linearSprings) {
    const double both = 1.0 / object.mass[s.a] + 1.0 / object.mass[s.b];
    rowSum[s.a] += both;
    rowSum[s.b] += both;
  }
  const double worst = rowSum.empty() ? 0.0 : *std::max_element(rowSum.begin(), rowSum.end());
  if (!(worst > 0.0)) return 0.0;
  // MODEL §2: ω² = κ · max_i Σ (1/m_i + 1/m_j) at the bound.
  return naturalFrequency * naturalFrequency / worst;
}

void resolveSprings(GeneratedObject& object, const SpringSettings& settings, double bendFactor) {
  constexpr const char* kSpec = "SpringSettings";
  check::nonNegative(kSpec, "stiffness", settings.stiffness, "N/m");
  check::nonNegative(kSpec, "damping", settings.damping, "N·s/m");
  check::nonNegative(kSpec, "bendStiffness", settings.bendStiffness, "N·m/rad");
  check::nonNegative(kSpec, "bendDamping", settings.bendDamping, "N·m·s/rad");
  check::positive(kSpec, "naturalFrequency", settings.naturalFrequency, "rad/s");
  check::nonNegative("resolveSprings", "bendFactor", bendFactor, "");
  const double minMass =
      object.mass.empty() ? 0.0 : *std::min_element(object.mass.begin(), object.mass.end());
  const double stiffness =
      settings.stiffness.value_or(defaultStiffness(object, settings.naturalFrequency));
  const double damping = settings.damping.value_or(0.2 * std::sqrt(stiffness * minMass / 2.0));
  for (auto& s : object.linearSprings) {
    s.stiffness = stiffness;
    s.damping = damping;
  }
  const double h2 = object.spacing * object.spacing;
  const double bend = settings.bendStiffness.value_or(bendFactor * stiffness * h2);
  const double bendDamping =
      settings.bendDamping.value_or(0.2 * std::sqrt(bend * minMass * h2 / 2.0));
  if (bend == 0.0 && bendDamping == 0.0) {
    object.torsionSprings.clear();
    return;
  }
  for (auto& s : object.torsionSprings) {
    s.stiffness = bend;
    s.damping = bendDamping;
  }
}

}  // namespace robophi::build
