// Calibrating a box lattice's connectors from elastic moduli (paper exp. 1,
// docs/bar-calibration.md). A simple cubic lattice of cell a with axis springs
// k1 and face-diagonal springs k2 (body diagonals off) is, in the bulk, a cubic
// material with C11 = (k1 + 2 k2)/a, C12 = C44 = k2/a; its Young's modulus along
// an axis is E = (k1 + k2)(k1 + 4 k2) / ((k1 + 3 k2) a) and its shear modulus G = k2/a.
#include <fmt/format.h>

#include <cmath>

#include "robotics/robot_builders.h"

namespace robophi::robotics {

bool calibrateLattice(io::ObjectReader& r, io::GeneratedObject& box, const Vec3& size,
                      const std::array<int, 3>& cells, double youngModulus,
                      std::optional<double> shearModulus) {
  const double a = size.x / cells[0];
  if (std::abs(size.y / cells[1] - a) > 1e-9 * a || std::abs(size.z / cells[2] - a) > 1e-9 * a) {
    r.sink().error(r.memberPointer("youngModulus"),
                   "'youngModulus' needs cubic cells (size / cells equal in x, y and z)");
    return false;
  }
  const double E = youngModulus;
  const double G = shearModulus.value_or(0.4 * E);
  // Bulk: k2 = G a, and k1 the positive root of (k1 + k2)(k1 + 4 k2) = E a (k1 + 3 k2).
  const double k2 = G * a;
  const double b = 5.0 * k2 - E * a, c = 4.0 * k2 * k2 - 3.0 * E * a * k2;
  const double k1 = 0.5 * (-b + std::sqrt(b * b - 4.0 * c));
  if (!(k1 > 0.0)) {
    r.sink().error(r.memberPointer("shearModulus"),
                   fmt::format("'shearModulus' {} Pa is too large for 'youngModulus' {} Pa: a "
                               "lattice of central springs needs G < 0.5 E",
                               G, E));
    return false;
  }
  double minMass = box.mass[0];
  for (double m : box.mass) minMass = std::min(minMass, m);
  for (LinearSpring& s : box.linearSprings) {
    const double ratio = s.restLength / a;
    const double k = ratio < 1.2 ? k1 : (ratio < 1.6 ? k2 : 0.0);
    s.stiffness = k;
    s.damping = 0.2 * std::sqrt(k * minMass / 2.0);
  }
  return true;
}

}  // namespace robophi::robotics
