// The LS of a rigid body (build/rigid_body_parts.h): lattice neighbours, ties
// that span 3-D, joins between pieces, and a rigidity check with bracing.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "build/rigid_body_parts.h"

namespace robophi::build::detail {

namespace {

// Spanning 3-D: the points' spread has no flat direction.
bool spans3d(const std::vector<Vec3>& points) {
  if (points.size() < 4) return false;
  Vec3 mean{};
  for (const Vec3& c : points) mean += c / static_cast<double>(points.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& c : points) {
    const Eigen::Vector3d d(c.x - mean.x, c.y - mean.y, c.z - mean.z);
    cov += d * d.transpose();
  }
  const Eigen::Vector3d ev =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov, Eigen::EigenvaluesOnly).eigenvalues();
  return ev(0) > 1e-3 * ev(2);
}

// Ties particle i to the body: when its LS neighbours are fewer than 4 or do
// not span 3-D (a required point, a carrier, a sheet of thin particles, a
// corner of a coarse lattice), LS to its nearest other particles (carriers
// aside) until they do, at most 64 more.
void tie(GeneratedObject& object, const std::vector<Particle>& particles, int i,
         std::vector<std::vector<int>>& linked) {
  auto& mine = linked[static_cast<std::size_t>(i)];
  std::vector<Vec3> around;
  for (const int j : mine) around.push_back(particles[static_cast<std::size_t>(j)].position);
  if (spans3d(around)) return;
  std::vector<int> order;
  for (int j = 0; j < static_cast<int>(particles.size()); ++j) {
    const bool taken = std::find(mine.begin(), mine.end(), j) != mine.end();
    if (j != i && !taken && particles[static_cast<std::size_t>(j)].role != Role::kCarrier) {
      order.push_back(j);
    }
  }
  const Vec3& p = particles[static_cast<std::size_t>(i)].position;
  std::sort(order.begin(), order.end(), [&](int l, int r) {
    const double dl = squaredNorm(particles[static_cast<std::size_t>(l)].position - p);
    const double dr = squaredNorm(particles[static_cast<std::size_t>(r)].position - p);
    return dl < dr || (dl == dr && l < r);
  });
  int added = 0;
  for (const int j : order) {
    if (added >= 64) break;
    addLink(object, i, j);
    mine.push_back(j);
    linked[static_cast<std::size_t>(j)].push_back(i);
    around.push_back(particles[static_cast<std::size_t>(j)].position);
    ++added;
    if (spans3d(around)) break;
  }
}

// The number of floppy modes of the LS framework beyond the 6 rigid motions:
// zero eigenvalues of K = Σ u uᵀ (u the unit LS directions), dense.
int mechanisms(const GeneratedObject& object) {
  const auto n = static_cast<Eigen::Index>(3 * object.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  for (const auto& s : object.linearSprings) {
    const Vec3 d = object.position[s.a] - object.position[s.b];
    const Eigen::Vector3d u = Eigen::Vector3d(d.x, d.y, d.z) / norm(d);
    const Eigen::Matrix3d block = u * u.transpose();
    k.block<3, 3>(3 * s.a, 3 * s.a) += block;
    k.block<3, 3>(3 * s.b, 3 * s.b) += block;
    k.block<3, 3>(3 * s.a, 3 * s.b) -= block;
    k.block<3, 3>(3 * s.b, 3 * s.a) -= block;
  }
  const Eigen::VectorXd ev =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k, Eigen::EigenvaluesOnly).eigenvalues();
  int zero = 0;
  for (Eigen::Index i = 0; i < n; ++i) zero += ev(i) < 1e-9 * ev(n - 1);
  return std::max(0, zero - 6);
}

// A coarse lattice can be a linkage (a ring of cells meeting at edges is a
// four-bar): bodies of up to kCheckedParticles particles are checked, and braced
// with LS to the pairs within 1.6, 2.2, 3, ... × the lattice reach until rigid.
// Returns the LS added.
constexpr std::size_t kCheckedParticles = 250;
int braceMechanisms(GeneratedObject& object, const std::vector<Particle>& particles) {
  if (object.size() > kCheckedParticles || mechanisms(object) == 0) return 0;
  double reach = 0.0;
  for (const auto& p : particles) reach = std::max(reach, p.reach);
  std::vector<std::pair<int, int>> existing;
  for (const auto& s : object.linearSprings)
    existing.emplace_back(std::min(s.a, s.b), std::max(s.a, s.b));
  std::sort(existing.begin(), existing.end());
  const std::size_t before = object.linearSprings.size();
  const int n = static_cast<int>(particles.size());
  for (const double factor : {1.6, 2.2, 3.0, 4.5, 1e9}) {
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        if (particles[static_cast<std::size_t>(i)].role == Role::kCarrier &&
            particles[static_cast<std::size_t>(j)].role == Role::kCarrier) {
          continue;
        }
        const double d = norm(particles[static_cast<std::size_t>(i)].position -
                              particles[static_cast<std::size_t>(j)].position);
        if (d > factor * reach) continue;
        const std::pair<int, int> pair{i, j};
        if (std::binary_search(existing.begin(), existing.end(), pair)) continue;
        addLink(object, i, j);
        existing.insert(std::upper_bound(existing.begin(), existing.end(), pair), pair);
      }
    }
    if (mechanisms(object) == 0) break;
  }
  return static_cast<int>(object.linearSprings.size() - before);
}

}  // namespace

int connect(GeneratedObject& object, const std::vector<Particle>& particles) {
  const int n = static_cast<int>(particles.size());
  std::vector<std::vector<int>> linked(static_cast<std::size_t>(n));
  double reach = 0.0;
  for (const auto& p : particles) {
    if (p.role == Role::kLattice) reach = std::max(reach, p.reach);
  }
  // Sorted sweep along x: pairs within `reach` in x, then by distance.
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int l, int r) {
    const double xl = particles[static_cast<std::size_t>(l)].position.x;
    const double xr = particles[static_cast<std::size_t>(r)].position.x;
    return xl < xr || (xl == xr && l < r);
  });
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t u = 0; u < order.size(); ++u) {
    const Particle& a = particles[static_cast<std::size_t>(order[u])];
    if (a.role != Role::kLattice) continue;
    for (std::size_t v = u + 1; v < order.size(); ++v) {
      const Particle& b = particles[static_cast<std::size_t>(order[v])];
      if (b.position.x - a.position.x > reach) break;
      if (b.role != Role::kLattice) continue;
      const double limit = std::max(a.reach, b.reach);
      if (squaredNorm(b.position - a.position) <= limit * limit) {
        pairs.emplace_back(std::min(order[u], order[v]), std::max(order[u], order[v]));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [a, b] : pairs) {
    addLink(object, a, b);
    linked[static_cast<std::size_t>(a)].push_back(b);
    linked[static_cast<std::size_t>(b)].push_back(a);
  }
  for (int i = 0; i < n; ++i) tie(object, particles, i, linked);

  // Join the pieces (shapes that only touch, parts apart) to the first: the
  // four particles of the nearest piece closest to the first piece, each by LS
  // to its three nearest there (12 LS: rigid, not a hinge or a ball joint).
  const auto flood = [&](int from, std::vector<int>& label, int id) {
    std::vector<int> stack{from};
    label[static_cast<std::size_t>(from)] = id;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      for (const int j : linked[static_cast<std::size_t>(i)]) {
        if (label[static_cast<std::size_t>(j)] < 0) {
          label[static_cast<std::size_t>(j)] = id;
          stack.push_back(j);
        }
      }
    }
  };
  const auto distance2 = [&](int i, int j) {
    return squaredNorm(particles[static_cast<std::size_t>(i)].position -
                       particles[static_cast<std::size_t>(j)].position);
  };
  for (;;) {
    std::vector<int> piece(static_cast<std::size_t>(n), -1);
    flood(0, piece, 0);
    // Each outside particle's distance to the first piece.
    std::vector<std::pair<double, int>> outside;
    for (int i = 0; i < n; ++i) {
      if (piece[static_cast<std::size_t>(i)] == 0) continue;
      double best = 1e300;
      for (int j = 0; j < n; ++j) {
        if (piece[static_cast<std::size_t>(j)] == 0) best = std::min(best, distance2(i, j));
      }
      outside.emplace_back(best, i);
    }
    if (outside.empty()) break;
    std::sort(outside.begin(), outside.end());
    flood(outside.front().second, piece, 1);
    int joined = 0;
    for (const auto& [d, i] : outside) {
      if (joined >= 4) break;
      if (piece[static_cast<std::size_t>(i)] != 1) continue;
      std::vector<std::pair<double, int>> near;
      for (int j = 0; j < n; ++j) {
        if (piece[static_cast<std::size_t>(j)] == 0) near.emplace_back(distance2(i, j), j);
      }
      std::sort(near.begin(), near.end());
      for (std::size_t k = 0; k < near.size() && k < 3; ++k) {
        addLink(object, i, near[k].second);
        linked[static_cast<std::size_t>(i)].push_back(near[k].second);
        linked[static_cast<std::size_t>(near[k].second)].push_back(i);
      }
      ++joined;
    }
  }
  return braceMechanisms(object, particles);
}

}  // namespace robophi::build::detail
