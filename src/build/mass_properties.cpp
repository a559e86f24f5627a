// Frames, mass properties of point sets and of shapes at uniform density
// (build/rigid_body.h).

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "build/shape_fill.h"
#include "robophi/build/rigid_body.h"

namespace robophi::build {

namespace {

Eigen::Matrix3d toMatrix(const Inertia& i) {
  Eigen::Matrix3d m;
  m << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  return m;
}

Inertia fromMatrix(const Eigen::Matrix3d& m) {
  return {m(0, 0),
          m(1, 1),
          m(2, 2),
          0.5 * (m(0, 1) + m(1, 0)),
          0.5 * (m(0, 2) + m(2, 0)),
          0.5 * (m(1, 2) + m(2, 1))};
}

Eigen::Matrix3d rotationOf(const Frame& frame) {
  Eigen::Matrix3d r;
  for (int j = 0; j < 3; ++j) r.col(j) << frame.axes[j].x, frame.axes[j].y, frame.axes[j].z;
  return r;
}

Eigen::Vector3d toEigen(const Vec3& v) { return {v.x, v.y, v.z}; }

// I = tr(S) 𝟙 − S from the second moments S = Σ m d dᵀ about the centre.
Inertia inertiaOfSecondMoments(const Eigen::Matrix3d& s) {
  return fromMatrix(s.trace() * Eigen::Matrix3d::Identity() - s);
}

// A shape alone: exact for primitives and closed meshes (false: sample it).
bool exactShapeProperties(const ShapeSpec& shape, double mass, MassProperties& out) {
  Eigen::Matrix3d local = Eigen::Matrix3d::Zero();  // inertia about the centre, shape axes
  Vec3 centre{};
  switch (shape.kind) {
    case ShapeSpec::Kind::kBox: {
      const Vec3& a = shape.size;
      local.diagonal() << mass * (a.y * a.y + a.z * a.z) / 12.0,
          mass * (a.x * a.x + a.z * a.z) / 12.0, mass * (a.x * a.x + a.y * a.y) / 12.0;
      break;
    }
    case ShapeSpec::Kind::kCylinder: {
      const double r2 = shape.radius * shape.radius, l2 = shape.length * shape.length;
      const double across = mass * (3.0 * r2 + l2) / 12.0;
      local.diagonal() << across, across, 0.5 * mass * r2;
      break;
    }
    case ShapeSpec::Kind::kSphere:
      local.diagonal().setConstant(0.4 * mass * shape.radius * shape.radius);
      break;
    case ShapeSpec::Kind::kMesh: {
      if (detail::openEdges(shape.mesh) > 0) return false;
      // Signed tetrahedra (0, a, b, c): volume det/6, ∫ x xᵀ dV = det/120 (Σ v vᵀ + s sᵀ).
      double volume = 0.0;
      Eigen::Vector3d first = Eigen::Vector3d::Zero();
      Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
      for (const auto& tri : shape.mesh.triangles) {
        const Eigen::Vector3d a = toEigen(shape.mesh.vertices[static_cast<std::size_t>(tri[0])]);
        const Eigen::Vector3d b = toEigen(shape.mesh.vertices[static_cast<std::size_t>(tri[1])]);
        const Eigen::Vector3d c = toEigen(shape.mesh.vertices[static_cast<std::size_t>(tri[2])]);
        const double det = a.dot(b.cross(c));
        const Eigen::Vector3d sum = a + b + c;
        volume += det / 6.0;
        first += det / 24.0 * sum;
        second +=
            det / 120.0 *
            (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
      }
      if (!(std::abs(volume) > 0.0)) return false;
      const Eigen::Vector3d c = first / volume;
      // Σ signs: an inward-wound mesh gives negative volume and moments alike.
      const Eigen::Matrix3d s = (second / volume - c * c.transpose()) * mass;
      local = toMatrix(inertiaOfSecondMoments(s));
      centre = {c.x(), c.y(), c.z()};
      break;
    }
  }
  const Eigen::Matrix3d r = rotationOf(shape.frame);
  out.mass = mass;
  out.centerOfMass = shape.frame.apply(centre);
  out.inertia = fromMatrix(r * local * r.transpose());
  return true;
}

}  // namespace

Vec3 Frame::rotate(const Vec3& local) const {
  return axes[0] * local.x + axes[1] * local.y + axes[2] * local.z;
}

Vec3 Frame::apply(const Vec3& local) const { return origin + rotate(local); }

Frame Frame::then(const Frame& child) const {
  Frame out;
  out.origin = apply(child.origin);
  for (int j = 0; j < 3; ++j) out.axes[j] = rotate(child.axes[j]);
  return out;
}

Frame Frame::inverse() const {
  Frame out;
  for (int j = 0; j < 3; ++j) out.axes[j] = {axes[0][j], axes[1][j], axes[2][j]};
  out.origin = -out.rotate(origin);
  return out;
}

RoundAbout roundAbout(const ShapeSpec& shape, const Vec3& point, const Vec3& axis) {
  if (shape.kind != ShapeSpec::Kind::kCylinder && shape.kind != ShapeSpec::Kind::kSphere)
    return RoundAbout::kNone;
  // Its centre on the line within 1e-3 of its radius; a cylinder's axis along it.
  if (norm(cross(shape.frame.origin - point, axis)) > 1e-3 * shape.radius) return RoundAbout::kNone;
  if (shape.kind == ShapeSpec::Kind::kSphere) return RoundAbout::kSphere;
  return norm(cross(shape.frame.rotate({0.0, 0.0, 1.0}), axis)) > 1e-3 ? RoundAbout::kNone
                                                                        : RoundAbout::kCylinder;
}

Frame Frame::fromXyzRpy(const Vec3& xyz, const Vec3& rpy) {
  // R = Rz(yaw) Ry(pitch) Rx(roll), written out.
  const double cr = std::cos(rpy.x), sr = std::sin(rpy.x);
  const double cp = std::cos(rpy.y), sp = std::sin(rpy.y);
  const double cy = std::cos(rpy.z), sy = std::sin(rpy.z);
  Frame out;
  out.origin = xyz;
  out.axes[0] = {cy * cp, sy * cp, -sp};
  out.axes[1] = {cy * sp * sr - sy * cr, sy * sp * sr + cy * cr, cp * sr};
  out.axes[2] = {cy * sp * cr + sy * sr, sy * sp * cr - cy * sr, cp * cr};
  return out;
}

Frame Frame::fromAxisAngle(const Vec3& axis, double angle) {
  const double length = norm(axis);
  if (!(length > 0.0) || !std::isfinite(length)) {
    throw SpecError("Frame", "axis", "'axis' must be non-zero and finite");
  }
  const Vec3 k = axis / length;
  const double c = std::cos(angle), s = std::sin(angle);
  Frame out;
  // Rodrigues: R v = v cos φ + (k × v) sin φ + k (k·v)(1 − cos φ).
  for (int j = 0; j < 3; ++j) {
    Vec3 e{};
    e = j == 0 ? Vec3{1, 0, 0} : (j == 1 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    out.axes[j] = e * c + cross(k, e) * s + k * (dot(k, e) * (1.0 - c));
  }
  return out;
}

MassProperties massProperties(const std::vector<Vec3>& position, const std::vector<double>& mass) {
  MassProperties out;
  Vec3 moment{};
  for (std::size_t i = 0; i < position.size(); ++i) {
    out.mass += mass[i];
    moment += position[i] * mass[i];
  }
  if (!(out.mass > 0.0)) return out;
  out.centerOfMass = moment / out.mass;
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < position.size(); ++i) {
    const Eigen::Vector3d d = toEigen(position[i] - out.centerOfMass);
    s += mass[i] * d * d.transpose();
  }
  out.inertia = inertiaOfSecondMoments(s);
  return out;
}

std::array<double, 3> principalMoments(const Inertia& inertia) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(toMatrix(inertia),
                                                              Eigen::EigenvaluesOnly);
  const Eigen::Vector3d v = solver.eigenvalues();  // ascending
  return {v(0), v(1), v(2)};
}

Inertia rotateInertia(const Inertia& inertia, const Frame& frame) {
  const Eigen::Matrix3d r = rotationOf(frame);
  return fromMatrix(r * toMatrix(inertia) * r.transpose());
}

MassProperties uniformMassProperties(const std::vector<ShapeSpec>& shapes, double mass) {
  MassProperties out;
  if (shapes.empty() || !(mass > 0.0)) return out;
  if (shapes.size() == 1 && exactShapeProperties(shapes[0], mass, out)) return out;
  // The union, sampled: the cells of a fine lattice per shape (those inside an
  // earlier shape dropped), each with its own second moments (by the lattice's
  // stretch along a prism's axes, see detail::fillShape, or added).
  const double spacing = detail::spacingFor(shapes, 40000);
  std::vector<detail::ShapeInside> inside;
  double weight = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& shape : shapes) {
    const detail::ShapeLattice lattice = detail::fillShape(shape, spacing);
    const Vec3& cell = lattice.cell;
    const double cellVolume = cell.x * cell.y * cell.z;
    // Each cell's own second moments where the lattice is not stretched.
    const Eigen::Matrix3d r = rotationOf(shape.frame);
    Eigen::Matrix3d own = Eigen::Matrix3d::Zero();
    own.diagonal() << (lattice.stretched[0] ? 0.0 : cell.x * cell.x / 12.0),
        (lattice.stretched[1] ? 0.0 : cell.y * cell.y / 12.0),
        (lattice.stretched[2] ? 0.0 : cell.z * cell.z / 12.0);
    own = r * own * r.transpose();
    for (const Vec3& p : lattice.position) {
      const bool earlier = std::any_of(inside.begin(), inside.end(),
                                       [&](const detail::ShapeInside& in) { return in(p); });
      if (earlier) continue;
      const Eigen::Vector3d x = toEigen(p);
      weight += cellVolume;
      first += cellVolume * x;
      second += cellVolume * (x * x.transpose() + own);
    }
    inside.emplace_back(shape);
  }
  if (!(weight > 0.0)) return out;
  const Eigen::Vector3d c = first / weight;
  const Eigen::Matrix3d s = (second / weight - c * c.transpose()) * mass;
  out.mass = mass;
  out.centerOfMass = {c.x(), c.y(), c.z()};
  out.inertia = inertiaOfSecondMoments(s);
  return out;
}

}  // namespace robophi::build
