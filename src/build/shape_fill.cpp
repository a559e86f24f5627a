#include "build/shape_fill.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <tuple>

#include "build/checks.h"
#include "build/mesh_memo.h"

namespace robophi::build::detail {

namespace {

double component(const Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

int cellsAlong(double extent, double spacing) {
  return std::max(2, static_cast<int>(std::lround(extent / spacing)));
}

// Cells of each axis-aligned ray column crossed by the mesh: the non-zero
// winding rule along +axis (entering through a face whose normal points against
// the ray counts +1). Adds to votes[cell] (inside) and reliable[cell] for the
// columns whose crossings sum to zero (closed along that ray).
void rayVote(const TriangleMesh& mesh, const VoxelGrid& grid, int axis,
             std::vector<std::uint8_t>& votes, std::vector<std::uint8_t>& reliable) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  const int nb = grid.n[b], nc = grid.n[c], na = grid.n[axis];
  const double lob = component(grid.lo, b), loc = component(grid.lo, c);
  const double cb = component(grid.cell, b), cc = component(grid.cell, c);
  // A tiny irrational shift keeps the ray columns off vertices and edges.
  const double shiftB = 1.23456789e-7 * cb, shiftC = 2.71828183e-7 * cc;
  struct Crossing {
    int column;
    double t;
    int sign;
  };
  std::vector<Crossing> crossings;
  for (const auto& tri : mesh.triangles) {
    const Vec3& p0 = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& p1 = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& p2 = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const double x0 = component(p0, b), y0 = component(p0, c);
    const double x1 = component(p1, b), y1 = component(p1, c);
    const double x2 = component(p2, b), y2 = component(p2, c);
    // The face normal's component along the ray (twice the projected area).
    const double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
    if (area == 0.0) continue;
    const double minB = std::min({x0, x1, x2}), maxB = std::max({x0, x1, x2});
    const double minC = std::min({y0, y1, y2}), maxC = std::max({y0, y1, y2});
    const int j0 = std::max(0, static_cast<int>(std::ceil((minB - lob - shiftB) / cb - 0.5)));
    const int j1 = std::min(nb - 1, static_cast<int>(std::floor((maxB - lob - shiftB) / cb - 0.5)));
    const int k0 = std::max(0, static_cast<int>(std::ceil((minC - loc - shiftC) / cc - 0.5)));
    const int k1 = std::min(nc - 1, static_cast<int>(std::floor((maxC - loc - shiftC) / cc - 0.5)));
    for (int j = j0; j <= j1; ++j) {
      const double yb = lob + (j + 0.5) * cb + shiftB;
      for (int k = k0; k <= k1; ++k) {
        const double yc = loc + (k + 0.5) * cc + shiftC;
        const double w0 = ((x1 - yb) * (y2 - yc) - (x2 - yb) * (y1 - yc)) / area;
        const double w1 = ((x2 - yb) * (y0 - yc) - (x0 - yb) * (y2 - yc)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const double t =
            w0 * component(p0, axis) + w1 * component(p1, axis) + w2 * component(p2, axis);
        crossings.push_back({j * nc + k, t, area > 0.0 ? -1 : 1});
      }
    }
  }
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& l, const Crossing& r) {
    return std::tie(l.column, l.t, l.sign) < std::tie(r.column, r.t, r.sign);
  });
  const double loa = component(grid.lo, axis), ca = component(grid.cell, axis);
  std::size_t first = 0;
  while (first < crossings.size()) {
    std::size_t last = first;
    int total = 0;
    while (last < crossings.size() && crossings[last].column == crossings[first].column) {
      total += crossings[last].sign;
      ++last;
    }
    if (total == 0) {
      const int j = crossings[first].column / nc, k = crossings[first].column % nc;
      int winding = 0;
      std::size_t next = first;
      for (int i = 0; i < na; ++i) {
        const double t = loa + (i + 0.5) * ca;
        while (next < last && crossings[next].t < t) winding += crossings[next++].sign;
        std::array<int, 3> at{};
        at[axis] = i;
        at[b] = j;
        at[c] = k;
        const std::size_t cell = grid.index(at[0], at[1], at[2]);
        ++reliable[cell];
        if (winding != 0) ++votes[cell];
      }
    }
    first = last;
  }
  // Columns with no crossing at all are reliably outside.
  std::vector<std::uint8_t> crossed(static_cast<std::size_t>(nb * nc), 0);
  for (const auto& x : crossings) crossed[static_cast<std::size_t>(x.column)] = 1;
  for (int j = 0; j < nb; ++j) {
    for (int k = 0; k < nc; ++k) {
      if (crossed[static_cast<std::size_t>(j * nc + k)]) continue;
      for (int i = 0; i < na; ++i) {
        std::array<int, 3> at{};
        at[axis] = i;
        at[b] = j;
        at[c] = k;
        ++reliable[grid.index(at[0], at[1], at[2])];
      }
    }
  }
}

// Marks the cells the triangles pass through (samples at most half a cell
// apart) and keeps the mean sample of each.
void markSurface(const TriangleMesh& mesh, VoxelGrid& grid) {
  const std::size_t cells = grid.inside.size();
  grid.surface.assign(cells, 0);
  grid.surfacePoint.assign(cells, Vec3{});
  std::vector<int> count(cells, 0);
  const auto cellOf = [&](const Vec3& p, std::size_t& out) {
    std::array<int, 3> at{};
    for (int a = 0; a < 3; ++a) {
      const int i = static_cast<int>(
          std::floor((component(p, a) - component(grid.lo, a)) / component(grid.cell, a)));
      at[a] = std::clamp(i, 0, grid.n[a] - 1);
    }
    out = grid.index(at[0], at[1], at[2]);
  };
  for (const auto& tri : mesh.triangles) {
    // Rows parallel to the longest edge (a → b), at most `step` apart across
    // it and along it: about area/step² samples, slivers included.
    std::array<Vec3, 3> p{mesh.vertices[static_cast<std::size_t>(tri[0])],
                          mesh.vertices[static_cast<std::size_t>(tri[1])],
                          mesh.vertices[static_cast<std::size_t>(tri[2])]};
    int longestEdge = 0;
    double longest = 0.0;
    for (int e = 0; e < 3; ++e) {
      const double l = norm(p[(e + 1) % 3] - p[e]);
      if (l > longest) {
        longest = l;
        longestEdge = e;
      }
    }
    const Vec3 a = p[longestEdge], b = p[(longestEdge + 1) % 3], o = p[(longestEdge + 2) % 3];
    const double height = longest > 0.0 ? norm(cross(b - a, o - a)) / longest : 0.0;
    // A step within the triangle's plane moves at most √(1 − n_a²) of it along
    // axis a: at most half a cell along every axis (a face of a flat cell is
    // not sampled at that cell's thickness).
    const Vec3 normal = cross(b - a, o - a);
    const double area2 = norm(normal);
    double step = 1e300;
    for (int axis = 0; axis < 3; ++axis) {
      const double na = area2 > 0.0 ? component(normal, axis) / area2 : 0.0;
      const double along = std::sqrt(std::max(1.0 - na * na, 0.0));
      if (along > 1e-9) step = std::min(step, 0.5 * component(grid.cell, axis) / along);
    }
    const int along = std::clamp(static_cast<int>(std::ceil(longest / step)), 1, 4096);
    const int across = std::clamp(static_cast<int>(std::ceil(height / step)), 1, 4096);
    for (int t = 0; t <= across; ++t) {
      const double v = static_cast<double>(t) / across;
      const Vec3 start = a + (o - a) * v, end = b + (o - b) * v;
      const int samples = std::max(1, static_cast<int>(std::ceil(along * (1.0 - v))));
      for (int u = 0; u <= samples; ++u) {
        const Vec3 q = start + (end - start) * (static_cast<double>(u) / samples);
        std::size_t cell = 0;
        cellOf(q, cell);
        grid.surface[cell] = 1;
        grid.surfacePoint[cell] += q;
        ++count[cell];
      }
    }
  }
  for (std::size_t i = 0; i < cells; ++i) {
    if (count[i] > 0) grid.surfacePoint[i] = grid.surfacePoint[i] / count[i];
  }
}

// Cells not reachable from the grid's border through cells that are neither
// surface nor inside: enclosed by an open mesh's surface.
int floodEnclosed(VoxelGrid& grid) {
  const auto& n = grid.n;
  std::vector<std::uint8_t> reached(grid.inside.size(), 0);
  std::vector<std::array<int, 3>> stack;
  const auto open = [&](int i, int j, int k) {
    const std::size_t c = grid.index(i, j, k);
    return !grid.surface[c] && !grid.inside[c] && !reached[c];
  };
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        const bool border =
            i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        if (border && open(i, j, k)) {
          reached[grid.index(i, j, k)] = 1;
          stack.push_back({i, j, k});
        }
      }
    }
  }
  while (!stack.empty()) {
    const auto at = stack.back();
    stack.pop_back();
    for (int a = 0; a < 3; ++a) {
      for (int d = -1; d <= 1; d += 2) {
        auto next = at;
        next[a] += d;
        if (next[a] < 0 || next[a] >= n[a]) continue;
        if (!open(next[0], next[1], next[2])) continue;
        reached[grid.index(next[0], next[1], next[2])] = 1;
        stack.push_back(next);
      }
    }
  }
  int added = 0;
  for (std::size_t c = 0; c < grid.inside.size(); ++c) {
    if (!reached[c] && !grid.surface[c] && !grid.inside[c]) {
      grid.inside[c] = 1;
      ++added;
    }
  }
  return added;
}

void meshBounds(const TriangleMesh& mesh, Vec3& lo, Vec3& hi) {
  lo = {1e300, 1e300, 1e300};
  hi = {-1e300, -1e300, -1e300};
  for (const auto& tri : mesh.triangles) {
    for (const int v : tri) {
      const Vec3& p = mesh.vertices[static_cast<std::size_t>(v)];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  }
  // A flat mesh (a sheet) gets a thickness of 1e-3 of its size, so that its
  // cells have a size.
  const Vec3 extent = hi - lo;
  const double floor = 1e-3 * std::max({extent.x, extent.y, extent.z, 1e-9});
  for (int a = 0; a < 3; ++a) {
    const double e = component(extent, a);
    if (e >= floor) continue;
    const double pad = 0.5 * (floor - e);
    (a == 0 ? lo.x : (a == 1 ? lo.y : lo.z)) -= pad;
    (a == 0 ? hi.x : (a == 1 ? hi.y : hi.z)) += pad;
  }
}

// A grid of n cells per axis over [lo, hi], classified for the mesh.
VoxelGrid meshGrid(const TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, std::array<int, 3> n,
                   MeshReport& report) {
  VoxelGrid grid;
  grid.lo = lo;
  grid.n = n;
  const Vec3 extent = hi - lo;
  grid.cell = {std::max(extent.x, 1e-9) / n[0], std::max(extent.y, 1e-9) / n[1],
               std::max(extent.z, 1e-9) / n[2]};
  classifyMesh(mesh, grid, report);
  return grid;
}

// A mesh's lattice in its own frame (fillShape): the cells inside, and a
// particle on each thin surface cell.
template <class Stretch>
MeshLattice meshLattice(const TriangleMesh& mesh, const Vec3& lo, const Vec3& hi,
                        std::array<int, 3> n, const Stretch& stretched) {
  MeshLattice out;
  const VoxelGrid grid = meshGrid(mesh, lo, hi, n, out.report);
  for (int i = 0; i < n[0]; ++i) {
    for (int j = 0; j < n[1]; ++j) {
      for (int k = 0; k < n[2]; ++k) {
        const std::size_t c = grid.index(i, j, k);
        if (grid.inside[c]) {
          out.local.push_back(stretched(grid.centre(i, j, k)));
          continue;
        }
        if (!grid.surface[c]) continue;
        // A thin part: surface here and no inside cell next to it gets a
        // particle on the surface, so that parts narrower than a cell are kept.
        bool nearInside = false;
        for (int di = -1; di <= 1 && !nearInside; ++di) {
          for (int dj = -1; dj <= 1 && !nearInside; ++dj) {
            for (int dk = -1; dk <= 1 && !nearInside; ++dk) {
              const int a = i + di, b = j + dj, cc = k + dk;
              if (a < 0 || b < 0 || cc < 0 || a >= n[0] || b >= n[1] || cc >= n[2]) continue;
              nearInside = grid.inside[grid.index(a, b, cc)] != 0;
            }
          }
        }
        if (nearInside) continue;
        out.local.push_back(grid.surfacePoint[c]);
        ++out.report.thinParticles;
      }
    }
  }
  return out;
}

}  // namespace

int openEdges(const TriangleMesh& mesh) {
  // Weld vertices at equal positions, then count each directed edge.
  std::vector<std::int32_t> order(mesh.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::int32_t>(i);
  const auto key = [&](std::int32_t i) {
    const Vec3& p = mesh.vertices[static_cast<std::size_t>(i)];
    return std::tie(p.x, p.y, p.z);
  };
  std::sort(order.begin(), order.end(), [&](std::int32_t l, std::int32_t r) {
    return key(l) < key(r) || (key(l) == key(r) && l < r);
  });
  std::vector<std::int32_t> weld(mesh.vertices.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    weld[static_cast<std::size_t>(order[i])] = i > 0 && key(order[i]) == key(order[i - 1])
                                                   ? weld[static_cast<std::size_t>(order[i - 1])]
                                                   : order[i];
  }
  // Each undirected edge (lo, hi) with +1 for lo→hi and −1 for hi→lo: closed
  // and consistently wound when every edge appears twice, once each way.
  std::vector<std::tuple<std::int32_t, std::int32_t, int>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const auto& tri : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const std::int32_t a = weld[static_cast<std::size_t>(tri[e])];
      const std::int32_t b = weld[static_cast<std::size_t>(tri[(e + 1) % 3])];
      if (a == b) continue;
      edges.emplace_back(std::min(a, b), std::max(a, b), a < b ? 1 : -1);
    }
  }
  std::sort(edges.begin(), edges.end());
  int open = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    int count = 0, balance = 0;
    while (j < edges.size() && std::get<0>(edges[j]) == std::get<0>(edges[i]) &&
           std::get<1>(edges[j]) == std::get<1>(edges[i])) {
      ++count;
      balance += std::get<2>(edges[j]);
      ++j;
    }
    if (count != 2 || balance != 0) ++open;
    i = j;
  }
  return open;
}

void classifyMesh(const TriangleMesh& mesh, VoxelGrid& grid, MeshReport& report) {
  const std::size_t cells = static_cast<std::size_t>(grid.n[0]) * grid.n[1] * grid.n[2];
  std::vector<std::uint8_t> votes(cells, 0), reliable(cells, 0);
  for (int axis = 0; axis < 3; ++axis) rayVote(mesh, grid, axis, votes, reliable);
  grid.inside.assign(cells, 0);
  for (std::size_t c = 0; c < cells; ++c)
    grid.inside[c] = reliable[c] > 0 && 2 * votes[c] > reliable[c];
  markSurface(mesh, grid);
  report.openEdges = openEdges(mesh);
  if (report.openEdges > 0) report.enclosedCells = floodEnclosed(grid);
}

void shapeBounds(const ShapeSpec& shape, Vec3& lo, Vec3& hi) {
  switch (shape.kind) {
    case ShapeSpec::Kind::kBox:
      hi = shape.size * 0.5;
      lo = -hi;
      return;
    case ShapeSpec::Kind::kCylinder:
      hi = {shape.radius, shape.radius, 0.5 * shape.length};
      lo = -hi;
      return;
    case ShapeSpec::Kind::kSphere:
      hi = {shape.radius, shape.radius, shape.radius};
      lo = -hi;
      return;
    case ShapeSpec::Kind::kMesh:
      meshBounds(shape.mesh, lo, hi);
      return;
  }
}

ShapeLattice fillShape(const ShapeSpec& shape, double spacing) {
  ShapeLattice out;
  Vec3 lo, hi;
  shapeBounds(shape, lo, hi);
  const Vec3 extent = hi - lo;
  // The lattice's size before it is allocated (a spacing far below the shape's
  // size asks for more cells than any body may have).
  const double cells = std::max(2.0, extent.x / spacing) * std::max(2.0, extent.y / spacing) *
                       std::max(2.0, extent.z / spacing);
  if (!(cells <= 16.0 * kMaxParticlesPerObject)) {
    throw SpecError("RigidBodySpec", "particleSize",
                    "a lattice spacing of " + check::number(spacing) + " m over a shape of " +
                        check::vector(extent) + " m makes " + check::number(std::round(cells)) +
                        " cells, more than the budget allows");
  }
  const std::array<int, 3> n{cellsAlong(extent.x, spacing), cellsAlong(extent.y, spacing),
                             cellsAlong(extent.z, spacing)};
  out.cell = {extent.x / n[0], extent.y / n[1], extent.z / n[2]};
  // Along the axes where the shape is a prism (a box's three, a cylinder's z),
  // cell centres are stretched about the middle by √(n²/(n² − 1)): equal point
  // masses then have the continuum's second moment (Σ ((i + ½)/n − ½)² =
  // (n² − 1)/12n against n/12), so that a uniform body needs no mass moved
  // outwards. Round sections and meshes keep the cell centres.
  const Vec3 middle = (lo + hi) * 0.5;
  Vec3 stretch{1.0, 1.0, 1.0};
  for (int a = 0; a < 3; ++a) {
    const bool prism =
        shape.kind == ShapeSpec::Kind::kBox || (shape.kind == ShapeSpec::Kind::kCylinder && a == 2);
    if (!prism) continue;
    const double nn = static_cast<double>(n[a]) * n[a];
    (a == 0 ? stretch.x : (a == 1 ? stretch.y : stretch.z)) = std::sqrt(nn / (nn - 1.0));
  }
  out.stretched = {stretch.x != 1.0, stretch.y != 1.0, stretch.z != 1.0};
  const auto stretched = [&](const Vec3& p) {
    const Vec3 d = p - middle;
    return middle + Vec3{d.x * stretch.x, d.y * stretch.y, d.z * stretch.z};
  };
  const auto keep = [&](const Vec3& p) {
    switch (shape.kind) {
      case ShapeSpec::Kind::kBox:
        return true;
      case ShapeSpec::Kind::kCylinder:
        return p.x * p.x + p.y * p.y <= shape.radius * shape.radius;
      case ShapeSpec::Kind::kSphere:
        return squaredNorm(p) <= shape.radius * shape.radius;
      case ShapeSpec::Kind::kMesh:
        return false;
    }
    return false;
  };
  if (shape.kind != ShapeSpec::Kind::kMesh) {
    for (int i = 0; i < n[0]; ++i) {
      for (int j = 0; j < n[1]; ++j) {
        for (int k = 0; k < n[2]; ++k) {
          const Vec3 p{lo.x + (i + 0.5) * out.cell.x, lo.y + (j + 0.5) * out.cell.y,
                       lo.z + (k + 0.5) * out.cell.z};
          if (keep(p)) out.position.push_back(shape.frame.apply(stretched(p)));
        }
      }
    }
    return out;
  }
  // A mesh's lattice before its frame, worked out once per mesh and spacing.
  const std::uint64_t digest = meshDigest(shape.mesh);
  MeshWorkMemo& memo = MeshWorkMemo::shared();
  std::shared_ptr<const MeshLattice> lattice = memo.lattice(shape.mesh, digest, spacing);
  if (lattice == nullptr) {
    lattice = std::make_shared<const MeshLattice>(meshLattice(shape.mesh, lo, hi, n, stretched));
    memo.keepLattice(shape.mesh, digest, spacing, lattice);
  }
  out.report = lattice->report;
  out.position.reserve(lattice->local.size());
  for (const Vec3& p : lattice->local) out.position.push_back(shape.frame.apply(p));
  return out;
}

double shapeVolume(const ShapeSpec& shape) {
  switch (shape.kind) {
    case ShapeSpec::Kind::kBox:
      return shape.size.x * shape.size.y * shape.size.z;
    case ShapeSpec::Kind::kCylinder:
      return std::numbers::pi * shape.radius * shape.radius * shape.length;
    case ShapeSpec::Kind::kSphere:
      return 4.0 / 3.0 * std::numbers::pi * shape.radius * shape.radius * shape.radius;
    case ShapeSpec::Kind::kMesh:
      break;
  }
  // Worked out once per mesh (build/mesh_memo.h).
  const std::uint64_t digest = meshDigest(shape.mesh);
  MeshWorkMemo& memo = MeshWorkMemo::shared();
  if (const std::optional<double> kept = memo.volume(shape.mesh, digest)) return *kept;
  const double volume = meshVolume(shape.mesh);
  memo.keepVolume(shape.mesh, digest, volume);
  return volume;
}

double meshVolume(const TriangleMesh& mesh) {
  double signedVolume = 0.0;
  for (const auto& tri : mesh.triangles) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    signedVolume += dot(a, cross(b, c)) / 6.0;
  }
  if (openEdges(mesh) == 0 && signedVolume != 0.0) return std::abs(signedVolume);
  Vec3 lo, hi;
  meshBounds(mesh, lo, hi);
  MeshReport report;
  const VoxelGrid grid = meshGrid(mesh, lo, hi, {48, 48, 48}, report);
  const double cellVolume = grid.cell.x * grid.cell.y * grid.cell.z;
  double volume = 0.0;
  for (std::size_t c = 0; c < grid.inside.size(); ++c) {
    if (grid.inside[c]) volume += cellVolume;
  }
  return volume;
}

double spacingFor(const std::vector<ShapeSpec>& shapes, int count) {
  // The volume per particle, or the area per particle for a sheet (a flat mesh).
  double volume = 0.0, area = 0.0;
  for (const auto& s : shapes) {
    volume += shapeVolume(s);
    for (const auto& t : s.mesh.triangles) {
      const Vec3& a = s.mesh.vertices[static_cast<std::size_t>(t[0])];
      area += 0.5 * norm(cross(s.mesh.vertices[static_cast<std::size_t>(t[1])] - a,
                               s.mesh.vertices[static_cast<std::size_t>(t[2])] - a));
    }
  }
  const double spacing = std::max(std::cbrt(volume / count), std::sqrt(0.5 * area / count));
  return spacing > 0.0 ? spacing : 1e-3;
}

ShapeInside::ShapeInside(const ShapeSpec& shape) : shape_(&shape), toShape_(shape.frame.inverse()) {
  if (shape.kind != ShapeSpec::Kind::kMesh) return;
  Vec3 lo, hi;
  meshBounds(shape.mesh, lo, hi);
  MeshReport report;
  grid_ = meshGrid(shape.mesh, lo, hi, {96, 96, 96}, report);
}

bool ShapeInside::operator()(const Vec3& bodyPoint) const {
  const Vec3 p = toShape_.apply(bodyPoint);
  switch (shape_->kind) {
    case ShapeSpec::Kind::kBox:
      return std::abs(p.x) <= 0.5 * shape_->size.x && std::abs(p.y) <= 0.5 * shape_->size.y &&
             std::abs(p.z) <= 0.5 * shape_->size.z;
    case ShapeSpec::Kind::kCylinder:
      return std::abs(p.z) <= 0.5 * shape_->length &&
             p.x * p.x + p.y * p.y <= shape_->radius * shape_->radius;
    case ShapeSpec::Kind::kSphere:
      return squaredNorm(p) <= shape_->radius * shape_->radius;
    case ShapeSpec::Kind::kMesh:
      break;
  }
  std::array<int, 3> at{};
  for (int a = 0; a < 3; ++a) {
    const double u = (component(p, a) - component(grid_.lo, a)) / component(grid_.cell, a);
    if (u < 0.0 || u >= grid_.n[a]) return false;
    at[a] = std::min(static_cast<int>(u), grid_.n[a] - 1);
  }
  const std::size_t c = grid_.index(at[0], at[1], at[2]);
  return grid_.inside[c] || grid_.surface[c];
}

}  // namespace robophi::build::detail
