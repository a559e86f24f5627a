#include "build/mass_fit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace robophi::build::detail {

namespace {

// The second moments about the centre of mass of an inertia tensor I:
// S = Σ m d dᵀ = tr(I)/2 𝟙 − I (I_xy = −Σ m d_x d_y).
Eigen::Matrix3d secondMoments(const Inertia& i) {
  Eigen::Matrix3d inertia;
  inertia << i.xx, i.xy, i.xz, i.xy, i.yy, i.yz, i.xz, i.yz, i.zz;
  return 0.5 * inertia.trace() * Eigen::Matrix3d::Identity() - inertia;
}

}  // namespace

MassFit fitMasses(const std::vector<Vec3>& position, const MassProperties& target,
                  double floorFraction, bool withInertia) {
  const auto n = static_cast<Eigen::Index>(position.size());
  MassFit fit;
  if (n == 0) return fit;
  // Unknowns u_i = m_i / m̄ (m̄ = M/n), lengths in units of L (the RMS distance
  // from the centre): every row of A u = b is O(n), and u starts at 1.
  const double meanMass = target.mass / static_cast<double>(n);
  double sumSquared = 0.0;
  for (const Vec3& p : position) sumSquared += squaredNorm(p - target.centerOfMass);
  const double length = std::max(std::sqrt(sumSquared / static_cast<double>(n)), 1e-12);
  Eigen::MatrixXd a(10, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 d = (position[static_cast<std::size_t>(i)] - target.centerOfMass) / length;
    a.col(i) << 1.0, d.x, d.y, d.z, d.x * d.x, d.y * d.y, d.z * d.z, d.x * d.y, d.x * d.z,
        d.y * d.z;
  }
  const Eigen::Matrix3d s = secondMoments(target.inertia) / (meanMass * length * length);
  Eigen::VectorXd b(10);
  b << static_cast<double>(n), 0.0, 0.0, 0.0, s(0, 0), s(1, 1), s(2, 2), s(0, 1), s(0, 2), s(1, 2);
  const Eigen::Index rows = withInertia ? 10 : 4;
  a.conservativeResize(rows, n);
  b.conservativeResize(rows);

  // The dual of min ½|u − 1|² subject to A u = b, u >= lo: u(λ) = max(lo, 1 + Aᵀλ)
  // maximises the Lagrangian's minimum g(λ), concave with gradient b − A u(λ);
  // Newton steps on the free set F (H = −A_F A_Fᵀ) with backtracking.
  const double lo = floorFraction;
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(rows);
  const auto primal = [&](const Eigen::VectorXd& l) {
    Eigen::VectorXd u = (Eigen::VectorXd::Ones(n) + a.transpose() * l).cwiseMax(lo);
    return u;
  };
  const auto dual = [&](const Eigen::VectorXd& l, const Eigen::VectorXd& u) {
    return 0.5 * (u - Eigen::VectorXd::Ones(n)).squaredNorm() - l.dot(a * u - b);
  };
  // Rows are O(n): 1e-10 n leaves the mass 1e-10 relative, the centre 1e-10 L
  // and the second moments 1e-10 relative (round-off stalls near 1e-11 n).
  const double tolerance = 1e-10 * static_cast<double>(n);
  Eigen::VectorXd u = primal(lambda);
  double value = dual(lambda, u);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Eigen::VectorXd gradient = b - a * u;
    if (gradient.lpNorm<Eigen::Infinity>() <= tolerance) {
      fit.feasible = true;
      break;
    }
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(rows, rows);
    const Eigen::VectorXd free = Eigen::VectorXd::Ones(n) + a.transpose() * lambda;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (free(i) > lo) h.selfadjointView<Eigen::Lower>().rankUpdate(a.col(i));
    }
    h = h.selfadjointView<Eigen::Lower>();
    h.diagonal().array() += 1e-12 * std::max(h.trace(), 1.0);
    const Eigen::VectorXd step = h.ldlt().solve(gradient);
    double t = 1.0;
    bool moved = false;
    for (int halving = 0; halving < 40; ++halving, t *= 0.5) {
      const Eigen::VectorXd trial = lambda + t * step;
      const Eigen::VectorXd trialU = primal(trial);
      const double trialValue = dual(trial, trialU);
      if (trialValue >= value + 1e-4 * t * gradient.dot(step)) {
        lambda = trial;
        u = trialU;
        value = trialValue;
        moved = true;
        break;
      }
    }
    // No ascent left with the conditions unmet, or λ running off: no feasible u.
    if (!moved || !(lambda.lpNorm<Eigen::Infinity>() < 1e12)) break;
  }
  if (!fit.feasible) {
    const Eigen::VectorXd gradient = b - a * u;
    fit.feasible = gradient.lpNorm<Eigen::Infinity>() <= tolerance;
  }
  // Mass exactly M whatever the outcome (the others as fitted).
  const double total = u.sum();
  fit.mass.resize(position.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    fit.mass[static_cast<std::size_t>(i)] = u(i) * target.mass / total;
  }
  return fit;
}

}  // namespace robophi::build::detail
