// The environment's geometry: ground planes, heightfield terrain, oriented boxes
// and spheres (MODEL §3, docs/contact.md).
#include "collision/environment.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace robophi {

namespace {

// Environment item kinds in the order of their numbering.
enum class ItemKind : std::uint8_t { kPlane, kHeightfield, kBox, kSphere };

ItemKind kindOf(const Environment& e, std::int32_t& item) {
  const auto planes = static_cast<std::int32_t>(e.planes.size());
  const auto fields = static_cast<std::int32_t>(e.heightfields.size());
  const auto boxes = static_cast<std::int32_t>(e.boxes.size());
  if (item < planes) return ItemKind::kPlane;
  item -= planes;
  if (item < fields) return ItemKind::kHeightfield;
  item -= fields;
  if (item < boxes) return ItemKind::kBox;
  item -= boxes;
  return ItemKind::kSphere;
}

// Signed distance to an oriented box and its outward normal (exact outside;
// inside, the nearest face).
double boxDistance(const BoxObstacle& box, const Vec3& p, Vec3& normal) {
  const Vec3 r = p - box.center;
  const double local[3] = {dot(r, box.axisX), dot(r, box.axisY), dot(r, box.axisZ)};
  const double half[3] = {box.halfExtents.x, box.halfExtents.y, box.halfExtents.z};
  double q[3], outside[3];
  double outsideSquared = 0.0;
  int nearest = 0;
  for (int k = 0; k < 3; ++k) {
    q[k] = std::abs(local[k]) - half[k];
    outside[k] = std::max(q[k], 0.0);
    outsideSquared += outside[k] * outside[k];
    if (q[k] > q[nearest]) nearest = k;
  }
  const Vec3* axes[3] = {&box.axisX, &box.axisY, &box.axisZ};
  if (outsideSquared > 0.0) {
    const double distance = std::sqrt(outsideSquared);
    normal = Vec3{};
    for (int k = 0; k < 3; ++k) {
      normal += *axes[k] * (std::copysign(outside[k], local[k]) / distance);
    }
    return distance;
  }
  normal = *axes[nearest] * (local[nearest] >= 0.0 ? 1.0 : -1.0);
  return q[nearest];
}

}  // namespace

bool Heightfield::covers(double x, double y) const {
  return x >= originX && y >= originY && x <= originX + (columns - 1) * cellSizeX &&
         y <= originY + (rows - 1) * cellSizeY;
}

namespace {

// The cell holding (x, y) (clamped onto the grid): its corner sample (i, j) and
// the fractions (tx, ty) across it.
struct CellPoint {
  int i, j;
  double tx, ty;
};

CellPoint cellPoint(const Heightfield& field, double x, double y) {
  const double fx = std::clamp((x - field.originX) / field.cellSizeX, 0.0,
                               static_cast<double>(field.columns - 1));
  const double fy =
      std::clamp((y - field.originY) / field.cellSizeY, 0.0, static_cast<double>(field.rows - 1));
  const int i = std::min(static_cast<int>(fx), field.columns - 2);
  const int j = std::min(static_cast<int>(fy), field.rows - 2);
  return {i, j, fx - i, fy - j};
}

}  // namespace

double Heightfield::heightAt(double x, double y, double* dhdx, double* dhdy) const {
  const auto [i, j, tx, ty] = cellPoint(*this, x, y);
  const auto at = [&](int ii, int jj) {
    return heights[static_cast<std::size_t>(jj) * columns + ii];
  };
  const double h00 = at(i, j), h10 = at(i + 1, j), h01 = at(i, j + 1), h11 = at(i + 1, j + 1);
  if (dhdx != nullptr) *dhdx = ((h10 - h00) * (1.0 - ty) + (h11 - h01) * ty) / cellSizeX;
  if (dhdy != nullptr) *dhdy = ((h01 - h00) * (1.0 - tx) + (h11 - h10) * tx) / cellSizeY;
  return (h00 * (1.0 - tx) + h10 * tx) * (1.0 - ty) + (h01 * (1.0 - tx) + h11 * tx) * ty;
}

void Heightfield::smoothedGradientAt(double x, double y, double g[2], double dgdx[2],
                                     double dgdy[2]) const {
  const auto [i, j, tx, ty] = cellPoint(*this, x, y);
  const auto at = [&](int ii, int jj) {
    return heights[static_cast<std::size_t>(jj) * columns + ii];
  };
  // The gradient at sample (ii, jj) by central differences (one-sided at the border).
  const auto gradient = [&](int ii, int jj, int axis) {
    const int i0 = std::max(ii - 1, 0), i1 = std::min(ii + 1, columns - 1);
    const int j0 = std::max(jj - 1, 0), j1 = std::min(jj + 1, rows - 1);
    return axis == 0 ? (at(i1, jj) - at(i0, jj)) / ((i1 - i0) * cellSizeX)
                     : (at(ii, j1) - at(ii, j0)) / ((j1 - j0) * cellSizeY);
  };
  for (int axis = 0; axis < 2; ++axis) {
    const double g00 = gradient(i, j, axis), g10 = gradient(i + 1, j, axis);
    const double g01 = gradient(i, j + 1, axis), g11 = gradient(i + 1, j + 1, axis);
    g[axis] = (g00 * (1.0 - tx) + g10 * tx) * (1.0 - ty) + (g01 * (1.0 - tx) + g11 * tx) * ty;
    dgdx[axis] = ((g10 - g00) * (1.0 - ty) + (g11 - g01) * ty) / cellSizeX;
    dgdy[axis] = ((g01 - g00) * (1.0 - tx) + (g11 - g10) * tx) / cellSizeY;
  }
}

Vec3 Heightfield::normalAt(double x, double y) const {
  double g[2], dgdx[2], dgdy[2];
  smoothedGradientAt(x, y, g, dgdx, dgdy);
  const Vec3 n{-g[0], -g[1], 1.0};
  return n / norm(n);
}

bool environmentDistance(const Environment& environment, std::int32_t item, const Vec3& p,
                         double& signedDistance, Vec3& normal) {
  switch (kindOf(environment, item)) {
    case ItemKind::kPlane: {
      const GroundPlane& plane = environment.planes[item];
      normal = plane.normal;
      signedDistance = dot(p - plane.point, plane.normal);
      return true;
    }
    case ItemKind::kHeightfield: {
      const Heightfield& field = environment.heightfields[item];
      const double x0 = field.originX, x1 = field.originX + (field.columns - 1) * field.cellSizeX;
      const double y0 = field.originY, y1 = field.originY + (field.rows - 1) * field.cellSizeY;
      if (!field.covers(p.x, p.y)) {
        // Beside the rectangle (MODEL §3.5): below the height of its edge, the
        // terrain's vertical side wall (the horizontal distance to the
        // rectangle); above it, the edge itself (a rounded rim), so that a
        // particle rolling off the edge keeps its contact until it clears it.
        Vec3 outside{p.x - std::clamp(p.x, x0, x1), p.y - std::clamp(p.y, y0, y1), 0.0};
        const double above = p.z - field.heightAt(p.x, p.y);
        if (above > 0.0) outside.z = above;
        const double distance = norm(outside);
        if (!(distance > 0.0)) return false;  // (a NaN position: no contact)
        signedDistance = distance;
        normal = outside / distance;
        return true;
      }
      // The vertical gap projected on the smoothed normal: d = (z - h) c with
      // c = n_z = 1 / sqrt(1 + |g|²), the distance to the tangent plane, exact on
      // a plane, close on gentle terrain. Both the height and the smoothed normal
      // are continuous, so the contact energy is too; and the normal returned is
      // d's own gradient, ∇d = c (-h_x, -h_y, 1) + (z - h) ∇c, made unit, so
      // that the contact force is the energy's gradient (the smoothed normal
      // itself leans off it where the terrain kinks: 19° on the cell of a 9 cm
      // step 5 cm wide, and a vehicle towed over it made 9 J of 132).
      double hx = 0.0, hy = 0.0;
      const double h = field.heightAt(p.x, p.y, &hx, &hy);
      double g[2], dgdx[2], dgdy[2];
      field.smoothedGradientAt(p.x, p.y, g, dgdx, dgdy);
      const double c = 1.0 / std::sqrt(1.0 + g[0] * g[0] + g[1] * g[1]);
      const double gap = p.z - h;
      const double c3 = c * c * c;
      const Vec3 gradient{-hx * c - gap * c3 * (g[0] * dgdx[0] + g[1] * dgdx[1]),
                          -hy * c - gap * c3 * (g[0] * dgdy[0] + g[1] * dgdy[1]), c};
      normal = gradient / norm(gradient);
      signedDistance = gap * c;
      if (signedDistance < 0.0) {
        // Nearer a side wall than the surface (a point that came in from a
        // side): pushed out through that wall, as from a box.
        const double sides[4] = {p.x - x0, x1 - p.x, p.y - y0, y1 - p.y};
        const Vec3 outward[4] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}};
        int nearest = 0;
        for (int k = 1; k < 4; ++k)
          if (sides[k] < sides[nearest]) nearest = k;
        if (sides[nearest] < -signedDistance) {
          signedDistance = -sides[nearest];
          normal = outward[nearest];
        }
      }
      return true;
    }
    case ItemKind::kBox:
      signedDistance = boxDistance(environment.boxes[item], p, normal);
      return true;
    case ItemKind::kSphere: {
      const SphereObstacle& sphere = environment.spheres[item];
      const Vec3 r = p - sphere.center;
      const double distance = norm(r);
      normal = distance > 0.0 ? r / distance : Vec3{0.0, 0.0, 1.0};
      signedDistance = distance - sphere.radius;
      return true;
    }
  }
  return false;
}

EnvironmentReach environmentReach(const Environment& environment, std::int32_t item) {
  std::int32_t local = item;
  EnvironmentReach reach;
  if (kindOf(environment, local) != ItemKind::kHeightfield) return reach;
  const Heightfield& field = environment.heightfields[local];
  if (field.heights.empty()) return reach;
  reach.top = *std::max_element(field.heights.begin(), field.heights.end());
  // The normal is interpolated between the samples' normals: its least n_z is a sample's.
  for (int j = 0; j < field.rows; ++j) {
    for (int i = 0; i < field.columns; ++i) {
      const Vec3 n = field.normalAt(field.originX + i * field.cellSizeX, field.originY + j * field.cellSizeY);
      if (n.z > 0.0) reach.steepness = std::max(reach.steepness, 1.0 / n.z);
    }
  }
  return reach;
}

bool environmentFarFrom(const Environment& environment, std::int32_t item, const Vec3& center,
                        double radius, const EnvironmentReach& reach) {
  std::int32_t local = item;
  if (kindOf(environment, local) == ItemKind::kHeightfield) {
    const Heightfield& field = environment.heightfields[local];
    const double xMax = field.originX + (field.columns - 1) * field.cellSizeX;
    const double yMax = field.originY + (field.rows - 1) * field.cellSizeY;
    if (center.x + radius < field.originX || center.x - radius > xMax ||
        center.y + radius < field.originY || center.y - radius > yMax) {
      return true;
    }
    return center.z - radius * reach.steepness > reach.top;
  }
  double signedDistance = 0.0;
  Vec3 normal;
  environmentDistance(environment, item, center, signedDistance, normal);
  return signedDistance > radius;
}

bool environmentBounds(const Environment& environment, std::int32_t item, Vec3& low, Vec3& high) {
  std::int32_t local = item;
  switch (kindOf(environment, local)) {
    case ItemKind::kPlane:
      return false;
    case ItemKind::kHeightfield: {
      const Heightfield& field = environment.heightfields[local];
      // The terrain is solid below its surface (MODEL §3.5): the box reaches
      // down without end, so that a particle under the lowest sample (one that
      // came in from a side, or a step that went deep) still finds its contact.
      const double highest = *std::max_element(field.heights.begin(), field.heights.end());
      low = {field.originX, field.originY, -std::numeric_limits<double>::infinity()};
      high = {field.originX + (field.columns - 1) * field.cellSizeX,
              field.originY + (field.rows - 1) * field.cellSizeY, highest};
      return true;
    }
    case ItemKind::kBox: {
      const BoxObstacle& box = environment.boxes[local];
      const Vec3 h = box.halfExtents;
      const Vec3 extent{
          std::abs(box.axisX.x) * h.x + std::abs(box.axisY.x) * h.y + std::abs(box.axisZ.x) * h.z,
          std::abs(box.axisX.y) * h.x + std::abs(box.axisY.y) * h.y + std::abs(box.axisZ.y) * h.z,
          std::abs(box.axisX.z) * h.x + std::abs(box.axisY.z) * h.y + std::abs(box.axisZ.z) * h.z};
      low = box.center - extent;
      high = box.center + extent;
      return true;
    }
    case ItemKind::kSphere: {
      const SphereObstacle& sphere = environment.spheres[local];
      const Vec3 r{sphere.radius, sphere.radius, sphere.radius};
      low = sphere.center - r;
      high = sphere.center + r;
      return true;
    }
  }
  return false;
}

std::int32_t environmentMaterial(const Environment& environment, std::int32_t item) {
  switch (kindOf(environment, item)) {
    case ItemKind::kPlane:
      return environment.planes[item].material;
    case ItemKind::kHeightfield:
      return environment.heightfields[item].material;
    case ItemKind::kBox:
      return environment.boxes[item].material;
    case ItemKind::kSphere:
      return environment.spheres[item].material;
  }
  return 0;
}

}  // namespace robophi
