// Geometry → a rigid body of mass-fitted particles (build/rigid_body.h).
// MODEL §1: the particles respect the reference object's mass, centre of mass
// and volume; here also its inertia tensor.

#include "robophi/build/rigid_body.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>

#include "build/checks.h"
#include "build/mass_fit.h"
#include "build/rigid_body_parts.h"
#include "build/shape_fill.h"

namespace robophi::build {

namespace {

using detail::Particle;
using detail::Role;

constexpr const char* kSpec = "RigidBodySpec";

bool allZero(const Inertia& i) {
  return i.xx == 0 && i.yy == 0 && i.zz == 0 && i.xy == 0 && i.xz == 0 && i.yz == 0;
}

// Three significant digits, for notes.
std::string brief(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

std::string shapeField(std::size_t index, const char* field) {
  return "shapes[" + std::to_string(index) + "]." + field;
}

void checkFrame(const Frame& frame, const std::string& field) {
  check::finite(kSpec, field.c_str(), frame.origin, "m");
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const double d = dot(frame.axes[a], frame.axes[b]);
      if (!(std::abs(d - (a == b ? 1.0 : 0.0)) < 1e-6)) {
        check::fail(kSpec, field.c_str(), "'" + field + "' axes must be orthonormal");
      }
    }
  }
  if (!(dot(cross(frame.axes[0], frame.axes[1]), frame.axes[2]) > 0.0)) {
    check::fail(kSpec, field.c_str(), "'" + field + "' axes must be right-handed");
  }
}

void checkSpec(const RigidBodySpec& spec) {
  check::positive(kSpec, "mass", spec.mass, "kg");
  check::finite(kSpec, "centerOfMass", spec.centerOfMass, "m");
  const Inertia& i = spec.inertia;
  for (const double v : {i.xx, i.yy, i.zz, i.xy, i.xz, i.yz}) {
    check::finite(kSpec, "inertia", v, "kg·m²");
  }
  if (!allZero(i)) {
    const auto moments = principalMoments(i);
    // Physical: positive definite, and the triangle inequality of the principal moments.
    if (!(moments[0] > 0.0) || moments[0] + moments[1] < moments[2] * (1.0 - 1e-9)) {
      check::fail(kSpec, "inertia",
                  "'inertia' is not a physical inertia tensor (principal moments " +
                      check::number(moments[0]) + ", " + check::number(moments[1]) + ", " +
                      check::number(moments[2]) +
                      " kg·m²: each must be > 0 and at most the "
                      "sum of the other two)");
    }
  }
  check::nonNegative(kSpec, "particleSize", spec.particleSize, "m");
  check::atLeast(kSpec, "particleCount", spec.particleCount, 1);
  check::atMost(kSpec, "particleCount", spec.particleCount, kMaxParticlesPerObject);
  if (!(spec.minMassFraction > 0.0 && spec.minMassFraction < 1.0)) {
    check::fail(kSpec, "minMassFraction",
                "'minMassFraction' must be in (0, 1), got " + check::number(spec.minMassFraction));
  }
  check::positive(kSpec, "naturalFrequency", spec.naturalFrequency, "rad/s");
  check::nonNegative(kSpec, "maxCarrierDistance", spec.maxCarrierDistance, "m");
  if (spec.uniformDensity && spec.shapes.empty()) {
    check::fail(kSpec, "uniformDensity", "'uniformDensity' needs at least one shape");
  }
  for (std::size_t k = 0; k < spec.requiredPoints.size(); ++k) {
    const std::string field = "requiredPoints[" + std::to_string(k) + "]";
    check::finite(kSpec, field.c_str(), spec.requiredPoints[k], "m");
  }
  for (std::size_t k = 0; k < spec.shapes.size(); ++k) {
    const ShapeSpec& s = spec.shapes[k];
    checkFrame(s.frame, shapeField(k, "frame"));
    switch (s.kind) {
      case ShapeSpec::Kind::kBox:
        check::positiveEach(kSpec, shapeField(k, "size").c_str(), s.size, "m");
        break;
      case ShapeSpec::Kind::kCylinder:
        check::positive(kSpec, shapeField(k, "radius").c_str(), s.radius, "m");
        check::positive(kSpec, shapeField(k, "length").c_str(), s.length, "m");
        break;
      case ShapeSpec::Kind::kSphere:
        check::positive(kSpec, shapeField(k, "radius").c_str(), s.radius, "m");
        break;
      case ShapeSpec::Kind::kMesh: {
        const std::string field = shapeField(k, "mesh");
        if (s.mesh.triangles.empty())
          check::fail(kSpec, field.c_str(), "'" + field + "' has no triangles");
        const auto count = static_cast<std::int32_t>(s.mesh.vertices.size());
        for (const auto& t : s.mesh.triangles) {
          for (const std::int32_t v : t) {
            if (v < 0 || v >= count) {
              check::fail(kSpec, field.c_str(),
                          "'" + field + "' has a triangle with vertex index " + std::to_string(v) +
                              " of " + std::to_string(count) + " vertices");
            }
          }
        }
        for (const Vec3& v : s.mesh.vertices) check::finite(kSpec, field.c_str(), v, "m");
        break;
      }
    }
  }
}

// The union's lattice at spacing h: each shape's cells, those inside an earlier
// shape dropped (so that overlaps are not filled twice).
std::vector<Particle> fillUnion(const std::vector<ShapeSpec>& shapes, double spacing,
                                std::vector<std::string>* notes) {
  std::vector<Particle> out;
  std::vector<detail::ShapeInside> earlier;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const detail::ShapeLattice lattice = detail::fillShape(shapes[k], spacing);
    const Vec3& cell = lattice.cell;
    // Half the cell's smallest side, at least a tenth of the spacing (a sheet).
    const double radius = std::max(0.5 * std::min({cell.x, cell.y, cell.z}), 0.1 * spacing);
    const double reach = 1.01 * norm(cell);
    for (std::size_t i = 0; i < lattice.position.size(); ++i) {
      const Vec3& p = lattice.position[i];
      if (std::any_of(earlier.begin(), earlier.end(),
                      [&](const detail::ShapeInside& in) { return in(p); })) {
        continue;
      }
      out.push_back({p, radius, reach, Role::kLattice});
    }
    if (shapes.size() > 1) earlier.emplace_back(shapes[k]);
    if (notes != nullptr && shapes[k].kind == ShapeSpec::Kind::kMesh) {
      const auto& r = lattice.report;
      const std::string which = "shapes[" + std::to_string(k) + "]";
      if (r.openEdges > 0) {
        notes->push_back(which + ": mesh not closed (" + std::to_string(r.openEdges) +
                         " open edges): inside by a 3-axis ray vote" +
                         (r.enclosedCells > 0 ? ", and " + std::to_string(r.enclosedCells) +
                                                    " cells its surface encloses"
                                              : std::string()));
      }
      if (r.thinParticles > 0) {
        notes->push_back(which + ": " + std::to_string(r.thinParticles) +
                         " particles on parts thinner than a cell");
      }
    }
  }
  return out;
}

// MODEL §1 (the particles respect the object's mass, centre and volume): the
// lattice mapped affinely, x' = c + A (x − g), so that equal masses have the
// uniform solid's centre c and second moments S (A S_lat Aᵀ = S, A symmetric:
// A = S^½ (S^½ S_lat S^½)^-½ S^½). Cell centres sit half a cell inside the
// surface, so a lattice falls short of the solid's second moments by about h²/12
// per axis; the map (a few % for a coarse lattice, a box's stretch already
// done) gives that back, and a uniform body fits with equal masses. Skipped
// when the map would stretch or shrink a direction by more than a third (a
// lattice too coarse to stand for the shape).
void matchUniformMoments(std::vector<Particle>& lattice, const MassProperties& uniform) {
  if (lattice.size() < 4 || !(uniform.mass > 0.0)) return;
  const auto n = static_cast<double>(lattice.size());
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const auto& p : lattice) g += Eigen::Vector3d(p.position.x, p.position.y, p.position.z) / n;
  Eigen::Matrix3d latticeS = Eigen::Matrix3d::Zero();
  for (const auto& p : lattice) {
    const Eigen::Vector3d d = Eigen::Vector3d(p.position.x, p.position.y, p.position.z) - g;
    latticeS += uniform.mass / n * d * d.transpose();
  }
  const Inertia& i = uniform.inertia;
  Eigen::Matrix3d inertia;
  inertia << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  const Eigen::Matrix3d solidS = 0.5 * inertia.trace() * Eigen::Matrix3d::Identity() - inertia;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solid(solidS);
  if (!(solid.eigenvalues().minCoeff() > 0.0) || !(latticeS.determinant() > 0.0)) return;
  const Eigen::Matrix3d root = solid.operatorSqrt();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> middle(root * latticeS * root);
  if (!(middle.eigenvalues().minCoeff() > 0.0)) return;
  const Eigen::Matrix3d map = root * middle.operatorInverseSqrt() * root;
  const Eigen::Vector3d stretch =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(map, Eigen::EigenvaluesOnly).eigenvalues();
  if (stretch.minCoeff() < 0.75 || stretch.maxCoeff() > 1.33) return;
  const Eigen::Vector3d c(uniform.centerOfMass.x, uniform.centerOfMass.y, uniform.centerOfMass.z);
  for (auto& p : lattice) {
    const Eigen::Vector3d x =
        c + map * (Eigen::Vector3d(p.position.x, p.position.y, p.position.z) - g);
    p.position = {x.x(), x.y(), x.z()};
  }
}

// The spacing whose lattice has the particle count nearest to `count`.
double chooseSpacing(const std::vector<ShapeSpec>& shapes, int count) {
  double spacing = detail::spacingFor(shapes, count);
  double best = spacing;
  long bestMiss = -1;
  for (int iteration = 0; iteration < 10; ++iteration) {
    const auto got = static_cast<long>(fillUnion(shapes, spacing, nullptr).size());
    const long miss = std::abs(got - count);
    if (bestMiss < 0 || miss < bestMiss) {
      bestMiss = miss;
      best = spacing;
    }
    if (miss == 0 || got == 0) break;
    const double factor = std::clamp(std::cbrt(static_cast<double>(got) / count), 0.7, 1.4);
    if (std::abs(factor - 1.0) < 1e-3) break;
    spacing *= factor;
  }
  return best;
}

// Principal axes (columns) and second moments S = tr(I)/2 𝟙 − I along them.
void principalSecondMoments(const Inertia& i, Eigen::Matrix3d& axes, Eigen::Vector3d& moments) {
  Eigen::Matrix3d inertia;
  inertia << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  const Eigen::Matrix3d s = 0.5 * inertia.trace() * Eigen::Matrix3d::Identity() - inertia;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(s);
  axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) *= -1.0;
  moments = solver.eigenvalues();
}

Vec3 column(const Eigen::Matrix3d& m, int j) { return {m(0, j), m(1, j), m(2, j)}; }

// No shapes: a centre and three pairs on the principal axes, masses M/7 each,
// at distances a_k with 2 (M/7) a_k² = S_k, so that the cluster carries the mass
// properties exactly (an axis of S_k ≈ 0 gets a small a_k, noted).
std::vector<Particle> cluster(const MassProperties& target, std::vector<std::string>& notes) {
  Eigen::Matrix3d axes;
  Eigen::Vector3d s;
  principalSecondMoments(target.inertia, axes, s);
  const double each = target.mass / 7.0;
  std::array<double, 3> a{};
  double largest = 0.0;
  for (int k = 0; k < 3; ++k) {
    a[k] = std::sqrt(std::max(s(k), 0.0) / (2.0 * each));
    largest = std::max(largest, a[k]);
  }
  if (!(largest > 0.0)) {
    // A point mass: a ball of water's density (1000 kg/m³).
    largest = std::cbrt(3.0 * target.mass / (4.0 * std::numbers::pi * 1000.0));
    notes.push_back("no shapes and no inertia: a cluster of the size of a water ball");
  }
  for (int k = 0; k < 3; ++k) {
    if (a[k] < 0.05 * largest) {
      a[k] = 0.05 * largest;
      notes.push_back("no shapes: a principal second moment too small for the cluster, raised");
    }
  }
  const double radius = 0.5 * std::min({a[0], a[1], a[2]});
  const double reach = 2.01 * std::max({a[0], a[1], a[2]});
  std::vector<Particle> out{{target.centerOfMass, radius, reach, Role::kLattice}};
  for (int k = 0; k < 3; ++k) {
    for (const double sign : {-1.0, 1.0}) {
      out.push_back(
          {target.centerOfMass + column(axes, k) * (sign * a[k]), radius, reach, Role::kLattice});
    }
  }
  notes.push_back("no shapes: a cluster of 7 particles carries the mass properties");
  return out;
}

std::vector<Vec3> positionsOf(const std::vector<Particle>& particles) {
  std::vector<Vec3> out;
  out.reserve(particles.size());
  for (const auto& p : particles) out.push_back(p.position);
  return out;
}

// The body's reach along each principal axis e_k of the target: the target's
// second moment S_k, the equal-mass lattice's U_k about the target centre, and
// the largest distance from that centre.
struct AxisReach {
  Eigen::Matrix3d axes;
  Eigen::Vector3d target, uniform, extent;
};
AxisReach axisReach(const std::vector<Particle>& particles, const MassProperties& target) {
  AxisReach r;
  principalSecondMoments(target.inertia, r.axes, r.target);
  const auto n = static_cast<double>(particles.size());
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = column(r.axes, k);
    r.uniform(k) = 0.0;
    r.extent(k) = 0.0;
    for (const auto& p : particles) {
      const double d = dot(p.position - target.centerOfMass, e);
      r.extent(k) = std::max(r.extent(k), std::abs(d));
      r.uniform(k) += target.mass / n * d * d;
    }
  }
  return r;
}

// Fits the masses; when the lattice cannot carry the target, adds carriers:
// pairs outside the geometry on the principal axes whose second moment it
// cannot reach, then six inner ones near the centre of mass that can take mass
// from the lattice when the inertia is below the lattice's reach, then eight
// on the diagonals, each farther in turn; then lowers the floor. Last resort:
// mass and centre exact, inertia as near as the fit got (body.fitted false).
detail::MassFit fitWithCarriers(std::vector<Particle>& particles, const MassProperties& target,
                                double floor, double spacing, double maxDistance, RigidBody& body) {
  detail::MassFit fit = detail::fitMasses(positionsOf(particles), target, floor);
  if (fit.feasible) return fit;
  const std::size_t base = particles.size();
  double smallestRadius = 1e300;
  for (const auto& p : particles) smallestRadius = std::min(smallestRadius, p.radius);
  const AxisReach reach = axisReach(particles, target);
  std::array<bool, 3> more{};
  bool anyMore = false, anyLess = false;
  for (int k = 0; k < 3; ++k) {
    more[k] = reach.target(k) > 0.8 * reach.uniform(k);
    anyMore = anyMore || more[k];
    anyLess = anyLess || reach.target(k) < reach.uniform(k);
  }
  struct Plan {
    bool inner;       // six near the centre of mass
    bool corners;     // eight on the diagonals (products of inertia of either sign)
    double distance;  // × the axis's carrier distance; 0: no outer carriers
  };
  std::vector<Plan> plans;
  if (anyMore) {
    for (const double f : {1.0, 1.6, 2.56}) plans.push_back({false, false, f});
  }
  const double axisPairs = anyMore || !anyLess ? 1.0 : 0.0;
  for (const double f : {1.0, 1.6, 2.56}) plans.push_back({true, false, axisPairs * f});
  for (const double f : {1.0, 1.6, 2.56, 4.1}) plans.push_back({true, true, f});
  // A carrier pair's distance from the centre: 1.25 × the body's extent, or
  // farther where a pair of mean-mass carriers (2 m̄ d² = S_k) is needed to carry
  // the axis's second moment (URDFs with placeholder inertias ask for that).
  const double meanMass = target.mass / static_cast<double>(base);
  Eigen::Vector3d distance;
  for (int k = 0; k < 3; ++k) {
    distance(k) = std::max({1.25 * reach.extent(k), 2.5 * smallestRadius,
                            std::sqrt(std::max(reach.target(k), 0.0) / (2.0 * meanMass))});
  }
  const auto clamp = [&](double d) { return maxDistance > 0.0 ? std::min(d, maxDistance) : d; };
  int outer = 0, inner = 0;
  const auto build = [&](const Plan& plan) {
    particles.resize(base);
    outer = inner = 0;
    for (int k = 0; k < 3 && plan.distance > 0.0; ++k) {
      if (anyMore && !more[k]) continue;
      const Vec3 e = column(reach.axes, k);
      for (const double sign : {-1.0, 1.0}) {
        particles.push_back({target.centerOfMass + e * (sign * clamp(plan.distance * distance(k))),
                             0.5 * smallestRadius, 0.0, Role::kCarrier});
        ++outer;
      }
    }
    for (int corner = 0; corner < 8 && plan.corners; ++corner) {
      // c + d (±e1 ±e2 ±e3)/√3: a lattice off to one side of its centre of mass
      // has products of inertia only these can cancel.
      Vec3 direction{};
      for (int k = 0; k < 3; ++k) {
        direction += column(reach.axes, k) * ((corner >> k & 1) != 0 ? 1.0 : -1.0);
      }
      particles.push_back(
          {target.centerOfMass +
               direction * (clamp(plan.distance * distance.maxCoeff()) / std::sqrt(3.0)),
           0.5 * smallestRadius, 0.0, Role::kCarrier});
      ++outer;
    }
    for (int k = 0; k < 3 && plan.inner; ++k) {
      for (const double sign : {-1.0, 1.0}) {
        const Vec3 p = target.centerOfMass + column(reach.axes, k) * (sign * 0.3 * spacing);
        const bool clash = std::any_of(particles.begin(), particles.end(), [&](const Particle& q) {
          return norm(q.position - p) < 0.15 * spacing;
        });
        if (clash) continue;
        particles.push_back({p, 0.15 * spacing, 0.0, Role::kCarrier});
        ++inner;
      }
    }
  };
  // Each floor with every plan (the lattice alone too, below the first floor).
  for (double lowered = floor; !fit.feasible && lowered > 0.02; lowered *= 0.5) {
    if (lowered < floor) plans.insert(plans.begin(), Plan{false, false, 0.0});
    for (const Plan& plan : plans) {
      build(plan);
      fit = detail::fitMasses(positionsOf(particles), target, lowered);
      if (fit.feasible) break;
    }
    if (lowered < floor) plans.erase(plans.begin());
    if (fit.feasible && lowered < floor) {
      body.notes.push_back("masses down to " + brief(lowered) +
                           " of the mean to reach the inertia");
    }
  }
  if (!fit.feasible) {
    // Out of reach: with the most capable carriers (else the lattice alone),
    // mass and centre fitted, then the inertia as far towards the one asked for
    // as it goes (bisection on t, I_t = I_0 + t (I − I_0), I_0 the inertia of
    // the mass-and-centre fit); else mass and centre only.
    const auto blend = [&](const Inertia& a, double t) {
      MassProperties m = target;
      const Inertia& b = target.inertia;
      m.inertia = {a.xx + t * (b.xx - a.xx), a.yy + t * (b.yy - a.yy), a.zz + t * (b.zz - a.zz),
                   a.xy + t * (b.xy - a.xy), a.xz + t * (b.xz - a.xz), a.yz + t * (b.yz - a.yz)};
      return m;
    };
    const auto want = principalMoments(target.inertia);
    const auto error = [&](const detail::MassFit& f) {
      const auto got = principalMoments(massProperties(positionsOf(particles), f.mass).inertia);
      double worst = 0.0;
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(got[k] - want[k]) / std::max(want[k], 1e-300));
      }
      return worst;
    };
    // The nearer of the two, with the most capable carriers or the lattice alone.
    detail::MassFit best;
    double bestError = 1e300;
    bool bestWithCarriers = false;
    for (const bool withCarriers : {true, false}) {
      if (withCarriers) {
        build(plans.back());
      } else {
        particles.resize(base);
        outer = inner = 0;
      }
      detail::MassFit reached = detail::fitMasses(positionsOf(particles), target, floor, false);
      if (!reached.feasible) continue;
      const Inertia start = massProperties(positionsOf(particles), reached.mass).inertia;
      double lo = 0.0, hi = 1.0;
      for (int halving = 0; halving < 12; ++halving) {
        const double t = 0.5 * (lo + hi);
        detail::MassFit trial = detail::fitMasses(positionsOf(particles), blend(start, t), floor);
        if (trial.feasible) {
          lo = t;
          reached = std::move(trial);
        } else {
          hi = t;
        }
      }
      if (const double e = error(reached); e < bestError) {
        bestError = e;
        best = std::move(reached);
        bestWithCarriers = withCarriers;
      }
    }
    if (best.mass.empty()) {
      particles.resize(base);
      outer = inner = 0;
      fit = detail::fitMasses(positionsOf(particles), target, floor, false);
      fit.feasible = false;
      body.notes.push_back(
          "inertia out of reach: mass and centre of mass fitted as near as can be");
    } else {
      if (bestWithCarriers) {
        build(plans.back());
      } else {
        particles.resize(base);
        outer = inner = 0;
      }
      fit = std::move(best);
      fit.feasible = false;  // not the target
      const auto got = principalMoments(massProperties(positionsOf(particles), fit.mass).inertia);
      body.notes.push_back(
          "inertia out of reach" +
          (maxDistance > 0.0 ? " (carriers within " + brief(maxDistance) + " m)" : std::string()) +
          ": principal moments " + brief(got[0]) + ", " + brief(got[1]) + ", " + brief(got[2]) +
          " kg·m² of " + brief(want[0]) + ", " + brief(want[1]) + ", " + brief(want[2]) + " asked");
    }
    if (outer + inner == 0) return fit;
  }
  if (outer > 0) {
    double farthest = 0.0, extent = 0.0;
    for (std::size_t i = base; i < particles.size(); ++i) {
      farthest = std::max(farthest, norm(particles[i].position - target.centerOfMass));
    }
    for (int k = 0; k < 3; ++k) extent = std::max(extent, reach.extent(k));
    body.notes.push_back("inertia beyond the geometry: " + std::to_string(outer) +
                         " carriers added, up to " + brief(farthest) +
                         " m from the centre of mass (the body reaches " + brief(extent) + " m)");
  }
  if (inner > 0) {
    body.notes.push_back("inertia out of the lattice's reach: " + std::to_string(inner) +
                         " carriers added near the centre of mass");
  }
  for (std::size_t i = base; i < particles.size(); ++i)
    body.carriers.push_back(static_cast<int>(i));
  return fit;
}

// True when the achieved properties are the target's within the stated tolerances.
bool matches(const MassProperties& got, const MassProperties& want) {
  if (!(std::abs(got.mass - want.mass) <= 1e-9 * want.mass)) return false;
  if (!(norm(got.centerOfMass - want.centerOfMass) <= 1e-6)) return false;
  const Inertia& a = got.inertia;
  const Inertia& b = want.inertia;
  const double scale = std::max(b.xx + b.yy + b.zz, 1e-300);
  for (const double d :
       {a.xx - b.xx, a.yy - b.yy, a.zz - b.zz, a.xy - b.xy, a.xz - b.xz, a.yz - b.yz}) {
    if (!(std::abs(d) <= 1e-6 * scale)) return false;
  }
  return true;
}

}  // namespace

RigidBody makeRigidBody(const RigidBodySpec& spec) {
  checkSpec(spec);
  RigidBody body;
  // What to carry: the spec's values, or the shapes' at uniform density.
  body.target.mass = spec.mass;
  body.target.centerOfMass = spec.centerOfMass;
  body.target.inertia = spec.inertia;
  MassProperties uniform;
  if (!spec.shapes.empty()) uniform = uniformMassProperties(spec.shapes, spec.mass);
  if (spec.uniformDensity || (allZero(spec.inertia) && !spec.shapes.empty())) {
    if (spec.uniformDensity) body.target.centerOfMass = uniform.centerOfMass;
    body.target.inertia = uniform.inertia;
    body.notes.push_back(spec.uniformDensity
                             ? "uniform density: centre of mass and inertia of the shapes"
                             : "no inertia given: the shapes' inertia at uniform density");
  }

  // The particles: the union's lattice (or a cluster), then the required points.
  std::vector<Particle> particles;
  if (!spec.shapes.empty()) {
    const double spacing = spec.particleSize > 0.0 ? spec.particleSize
                                                   : chooseSpacing(spec.shapes, spec.particleCount);
    double estimate = 0.0;
    for (const auto& s : spec.shapes) {
      Vec3 lo, hi;
      detail::shapeBounds(s, lo, hi);
      const Vec3 e = hi - lo;
      estimate += std::max(2.0, e.x / spacing) * std::max(2.0, e.y / spacing) *
                  std::max(2.0, e.z / spacing);
    }
    check::fitsBudget(kSpec, "particleSize", "'particleSize' " + check::number(spacing) + " m",
                      estimate, 13.0 * estimate);
    body.spacing = spacing;
    particles = fillUnion(spec.shapes, spacing, &body.notes);
    if (particles.empty()) {
      check::fail(
          kSpec, "shapes",
          "the shapes hold no lattice point at 'particleSize' " + check::number(spacing) + " m");
    }
    matchUniformMoments(particles, uniform);
  } else {
    particles = cluster(body.target, body.notes);
    body.spacing = 2.0 * particles[0].radius;
  }
  const std::size_t latticeCount = particles.size();
  for (const Vec3& point : spec.requiredPoints) {
    // A lattice particle close by moves onto the point; otherwise a new particle.
    int nearest = -1;
    double best = 1e300;
    for (std::size_t i = 0; i < latticeCount; ++i) {
      const double d = squaredNorm(particles[i].position - point);
      const bool taken = std::find(body.required.begin(), body.required.end(),
                                   static_cast<int>(i)) != body.required.end();
      if (!taken && d < best) {
        best = d;
        nearest = static_cast<int>(i);
      }
    }
    if (nearest >= 0 &&
        std::sqrt(best) <= 0.7 * particles[static_cast<std::size_t>(nearest)].radius) {
      particles[static_cast<std::size_t>(nearest)].position = point;
      particles[static_cast<std::size_t>(nearest)].role = Role::kRequired;
      body.required.push_back(nearest);
    } else {
      const double radius =
          nearest >= 0 ? particles[static_cast<std::size_t>(nearest)].radius : 0.5 * body.spacing;
      body.required.push_back(static_cast<int>(particles.size()));
      particles.push_back({point, radius, 0.0, Role::kRequired});
    }
  }

  const detail::MassFit fit = fitWithCarriers(particles, body.target, spec.minMassFraction,
                                              body.spacing, spec.maxCarrierDistance, body);

  GeneratedObject& object = body.object;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    addParticle(object, particles[i].position, fit.mass[i], particles[i].radius);
  }
  object.spacing = body.spacing;
  if (const int braces = detail::connect(object, particles); braces > 0) {
    body.notes.push_back("lattice braced with " + std::to_string(braces) +
                         " longer LS (alone it was a linkage, not rigid)");
  }
  check::fitsBudget(kSpec, "particleSize", "the lattice", static_cast<double>(object.size()),
                    static_cast<double>(object.linearSprings.size()));
  // Stiffness from the natural-frequency rule (objects.h defaultStiffness).
  SpringSettings springs;
  springs.naturalFrequency = spec.naturalFrequency;
  resolveSprings(object, springs);

  body.achieved = massProperties(object.position, object.mass);
  body.fitted = fit.feasible && matches(body.achieved, body.target);
  if (!body.fitted) {
    const auto want = principalMoments(body.target.inertia);
    const auto got = principalMoments(body.achieved.inertia);
    double worst = 0.0;
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(got[k] - want[k]) / std::max(want[k], 1e-300));
    }
    body.notes.push_back("mass fit not exact: centre of mass off by " +
                         brief(norm(body.achieved.centerOfMass - body.target.centerOfMass)) +
                         " m, principal moments by up to " + brief(100.0 * worst) + " %");
  }
  return body;
}

}  // namespace robophi::build
