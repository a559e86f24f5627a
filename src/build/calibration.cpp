// Calibrating a box lattice's connectors from elastic moduli (paper experiment 1,
// docs/robotics.md#bar-calibration-experiment-1).
//
// Bulk: a simple cubic lattice of cell a with axis springs k1 and face-diagonal
// springs k2 (body diagonals off) is a cubic material with C11 = (k1 + 2 k2)/a,
// C12 = C44 = k2/a; its Young's modulus along an axis is
// E = (k1 + k2)(k1 + 4 k2) / ((k1 + 3 k2) a) and its shear modulus G = k2/a.
//
// Bar: a slender box ((n − 1) a >= 3 × its width) is calibrated as a beam. A
// thin lattice bar is softer than the bulk (its surface lacks springs, its
// fibres sit at the cell centres), so starting from the bulk values Newton's
// method solves for the knobs that make the linearised lattice, clamped at its
// first layer and loaded on its last, exactly as stiff as beam theory:
//   - the axial springs' scale          ↔ traction  E·A/L,
//   - the longitudinal diagonals' scale ↔ torsion   G·J/L,
//   - TS along every fibre (bending)    ↔ flexion   3·E·I/L³,
//   - rectangular sections only: a tilt of the axial springs' stiffness towards
//     the wide side ↔ the ratio of the two flexions.
// Each Newton step is one band Cholesky factorisation of the stiffness matrix
// and four solves; the derivatives are exact (d log S / dκ = uᵀ ∂K u / fᵀu).
#include "robophi/build/calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "build/checks.h"

namespace robophi::build {

namespace {

// A box is calibrated as a beam when its length between the clamped and the
// loaded layer, (n − 1) a, is at least this many times its larger width.
constexpr double kMinSlenderness = 3.0;
// Newton stops when every |log(measured / target)| is below this (0.1 %).
constexpr double kTolerance = 1e-3;
constexpr int kMaxIterations = 20;
// The largest calibration accepted: multiply-adds of one factorisation (a few
// seconds for all the Newton steps) and doubles of its band (200 MB).
constexpr double kMaxWork = 3e9, kMaxBand = 2.5e7;

double component(const Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

// LS by direction relative to the beam axis.
enum Family : int {
  kAxial,            // axis springs along the beam axis
  kTransverse,       // axis springs across it
  kLongDiagonal,     // face diagonals in planes containing the axis
  kSectionDiagonal,  // face diagonals in the cross-section plane
  kBodyDiagonal,
};

// The torsion constant of a b × t rectangle (Saint-Venant, series solution):
// J = (b t³ / 3) [1 − (192 t / (π⁵ b)) Σ_{n odd} tanh(n π b / (2 t)) / n⁵], b >= t;
// 0.1406 h⁴ for a square.
double torsionConstant(double b, double t) {
  if (t > b) std::swap(b, t);
  double sum = 0.0;
  for (int n = 1; n < 100; n += 2)
    sum += std::tanh(n * std::numbers::pi * b / (2.0 * t)) / std::pow(n, 5);
  return b * t * t * t / 3.0 * (1.0 - 192.0 * t / (std::pow(std::numbers::pi, 5) * b) * sum);
}

// The lattice seen as a beam: its axis, cells and coordinates across.
struct BeamLattice {
  int axis = 0;
  std::array<int, 2> across{1, 2};    // the two axes across the beam
  std::array<int, 3> count{1, 1, 1};  // cells along the axis, across[0], across[1]
  double a = 0.0;
  std::vector<int> layer;      // per particle: cell index along the axis
  std::vector<int> fibre;      // per particle: j·count[2] + k, its cell across
  std::vector<double> y, z;    // per particle: coordinates along across[0], [1] (m)
  std::vector<Family> family;  // per LS
  // Per LS: for axial springs, the tilt weight (y² − ⟨y²⟩ − z² + ⟨z²⟩)/a² of
  // their fibre; 0 for the others.
  std::vector<double> tilt;
  std::vector<std::array<int, 3>> bends;  // (a, c, b) triples along the fibres
};

// False if the particles are not the full lattice of makeBox.
bool describeBeam(const GeneratedObject& box, const std::array<int, 3>& cells, double a, int axis,
                  BeamLattice& beam) {
  beam.axis = axis;
  beam.across = {(axis + 1) % 3, (axis + 2) % 3};
  beam.count = {cells[axis], cells[beam.across[0]], cells[beam.across[1]]};
  beam.a = a;
  const std::size_t n = box.size();
  if (n != static_cast<std::size_t>(cells[0]) * cells[1] * cells[2]) return false;
  Vec3 low = box.position[0], centre;
  for (const Vec3& p : box.position) {
    low = Vec3{std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    centre += p / static_cast<double>(n);
  }
  // The particle of each cell, fibre by fibre.
  std::vector<int> at(n, -1);
  beam.layer.resize(n);
  beam.fibre.resize(n);
  beam.y.resize(n);
  beam.z.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    std::array<int, 3> q{};
    for (int c = 0; c < 3; ++c)
      q[c] = static_cast<int>(std::lround(component(box.position[p] - low, c) / a));
    const int i = q[axis], j = q[beam.across[0]], k = q[beam.across[1]];
    if (i < 0 || j < 0 || k < 0 || i >= beam.count[0] || j >= beam.count[1] || k >= beam.count[2])
      return false;
    beam.layer[p] = i;
    beam.fibre[p] = j * beam.count[2] + k;
    beam.y[p] = component(box.position[p] - centre, beam.across[0]);
    beam.z[p] = component(box.position[p] - centre, beam.across[1]);
    int& cell = at[static_cast<std::size_t>(beam.fibre[p] * beam.count[0] + i)];
    if (cell >= 0) return false;
    cell = static_cast<int>(p);
  }
  for (int fibre = 0; fibre < beam.count[1] * beam.count[2]; ++fibre) {
    const auto cell = [&](int i) {
      return at[static_cast<std::size_t>(fibre * beam.count[0] + i)];
    };
    for (int i = 1; i + 1 < beam.count[0]; ++i)
      beam.bends.push_back({cell(i - 1), cell(i), cell(i + 1)});
  }
  // ⟨y²⟩ over the fibres: (count² − 1) a² / 12.
  const double meanY2 = (beam.count[1] * beam.count[1] - 1) / 12.0;
  const double meanZ2 = (beam.count[2] * beam.count[2] - 1) / 12.0;
  for (const LinearSpring& s : box.linearSprings) {
    const Vec3 d = box.position[s.b] - box.position[s.a];
    const bool along = std::abs(component(d, axis)) > 0.5 * a;
    int nonZero = 0;
    for (int c = 0; c < 3; ++c) nonZero += std::abs(component(d, c)) > 0.5 * a ? 1 : 0;
    const Family f = nonZero == 1   ? (along ? kAxial : kTransverse)
                     : nonZero == 2 ? (along ? kLongDiagonal : kSectionDiagonal)
                                    : kBodyDiagonal;
    beam.family.push_back(f);
    const auto p = static_cast<std::size_t>(s.a);
    const double y = beam.y[p] / a, z = beam.z[p] / a;
    beam.tilt.push_back(f == kAxial ? y * y - meanY2 - (z * z - meanZ2) : 0.0);
  }
  return true;
}

// The calibrated knobs: scales of the bulk axial and longitudinal-diagonal
// springs, the fibres' TS stiffness in units of E a³/12 (a fibre's own cell as
// a beam), and the tilt of the axial springs (rectangular sections).
struct Knobs {
  double axial = 1.0, diagonal = 1.0, bend = 1.0, tilt = 0.0;
};
constexpr int kKnobs = 4;

// The loads of the test, in this order: traction, flexion along across[0],
// flexion along across[1], torsion.
constexpr int kLoads = 4;

struct Response {
  // Static stiffness (N/m, N·m/rad) and its derivatives by (log axial,
  // log diagonal, bend, tilt).
  std::array<double, kLoads> stiffness{};
  std::array<std::array<double, kKnobs>, kLoads> dLog{};
};

// A symmetric positive definite band matrix of half-bandwidth w, factorised in
// place as L Lᵀ (row i keeps columns i − w .. i, contiguous). With the bar's
// degrees of freedom numbered layer by layer, w is two layers (a TS spans
// three), and a factorisation costs n w² / 2.
class BandCholesky {
 public:
  BandCholesky(Eigen::Index n, Eigen::Index w)
      : n_(n), w_(w), band_(static_cast<std::size_t>(n * (w + 1)), 0.0) {}

  // Adds v to A(i, j), i >= j (the lower triangle).
  void add(Eigen::Index i, Eigen::Index j, double v) { band_[index(i, j)] += v; }

  // False when A is not positive definite (the lattice is a mechanism).
  bool factorize() {
    for (Eigen::Index i = 0; i < n_; ++i) {
      const Eigen::Index first = std::max<Eigen::Index>(0, i - w_);
      for (Eigen::Index j = first; j <= i; ++j) {
        const double s = band_[index(i, j)] - row(i, first, j).dot(row(j, first, j));
        if (j < i) {
          band_[index(i, j)] = s / band_[index(j, j)];
        } else {
          if (!(s > 0.0)) return false;
          band_[index(i, i)] = std::sqrt(s);
        }
      }
    }
    return true;
  }

  // Solves A x = b in place (x holds b on entry).
  void solve(Eigen::Ref<Eigen::VectorXd> x) const {
    for (Eigen::Index i = 0; i < n_; ++i) {
      const Eigen::Index first = std::max<Eigen::Index>(0, i - w_);
      x(i) = (x(i) - row(i, first, i).dot(x.segment(first, i - first))) / band_[index(i, i)];
    }
    for (Eigen::Index i = n_ - 1; i >= 0; --i) {
      x(i) /= band_[index(i, i)];
      const Eigen::Index first = std::max<Eigen::Index>(0, i - w_);
      x.segment(first, i - first) -= x(i) * row(i, first, i);
    }
  }

 private:
  std::size_t index(Eigen::Index i, Eigen::Index j) const {
    return static_cast<std::size_t>(i * (w_ + 1) + (j - i + w_));
  }
  // Row i of L, columns [from, to).
  Eigen::Map<const Eigen::VectorXd> row(Eigen::Index i, Eigen::Index from, Eigen::Index to) const {
    return {band_.data() + index(i, from), to - from};
  }

  Eigen::Index n_, w_;
  std::vector<double> band_;
};

// The linearised static stiffness of the bar clamped at layer 0 (an LS adds
// κ n nᵀ at rest; a TS at 180° adds κ Σ_t (c ⊗ t)(c ⊗ t)ᵀ over the directions
// t normal to its fibre, c = (1, −2, 1)/a) and its response to the four loads.
class BeamStatics {
 public:
  BeamStatics(const GeneratedObject& box, const BeamLattice& beam, std::vector<double> base,
              double bendUnit)
      : box_(box), beam_(beam), base_(std::move(base)), bendUnit_(bendUnit) {
    const std::size_t n = box.size();
    const Eigen::Index section = beam.count[1] * beam.count[2];
    dof_.assign(n, -1);
    for (std::size_t p = 0; p < n; ++p) {
      if (beam.layer[p] > 0) dof_[p] = 3 * ((beam.layer[p] - 1) * section + beam.fibre[p]);
    }
    size_ = 3 * (beam.count[0] - 1) * section;
    width_ = 6 * section + 2;  // a TS spans three layers; an LS two
    for (const LinearSpring& s : box.linearSprings) {
      const Eigen::Index da = dof_[static_cast<std::size_t>(s.a)];
      const Eigen::Index db = dof_[static_cast<std::size_t>(s.b)];
      if (da >= 0 && db >= 0) width_ = std::max(width_, std::abs(da - db) + 2);
    }
    width_ = std::min(width_, size_ - 1);
    loads_ = Eigen::MatrixXd::Zero(size_, kLoads);
    double endCount = 0.0;
    for (std::size_t p = 0; p < n; ++p) endCount += beam.layer[p] == beam.count[0] - 1 ? 1.0 : 0.0;
    for (std::size_t p = 0; p < n; ++p) {
      if (beam.layer[p] != beam.count[0] - 1) continue;
      const Eigen::Index d = dof_[p];
      // Uniform forces of 1 N in total; a couple of tangential forces ∝ r.
      loads_(d + beam.axis, 0) = 1.0 / endCount;
      loads_(d + beam.across[0], 1) = 1.0 / endCount;
      loads_(d + beam.across[1], 2) = 1.0 / endCount;
      loads_(d + beam.across[0], 3) = -beam.z[p];
      loads_(d + beam.across[1], 3) = beam.y[p];
      total_[3] += beam.y[p] * beam.y[p] + beam.z[p] * beam.z[p];
    }
  }

  // Multiply-adds of one factorisation, and doubles of its band.
  double work() const {
    return 0.5 * static_cast<double>(size_) * static_cast<double>(width_) *
           static_cast<double>(width_);
  }
  double memory() const { return static_cast<double>(size_) * static_cast<double>(width_ + 1); }

  double stiffness(std::size_t s, const Knobs& knobs) const {
    switch (beam_.family[s]) {
      case kAxial:
        return base_[s] * knobs.axial * (1.0 + knobs.tilt * beam_.tilt[s]);
      case kLongDiagonal:
        return base_[s] * knobs.diagonal;
      default:
        return base_[s];
    }
  }

  // The response to the loads; false if the lattice is a mechanism.
  bool solve(const Knobs& knobs, Response& out) const {
    BandCholesky matrix(size_, width_);
    assemble(knobs, matrix);
    if (!matrix.factorize()) return false;
    Eigen::MatrixXd U = loads_;
    for (int l = 0; l < kLoads; ++l) matrix.solve(U.col(l));
    if (!U.allFinite()) return false;
    for (int l = 0; l < kLoads; ++l) {
      const auto ll = static_cast<std::size_t>(l);
      const double compliance = loads_.col(l).dot(U.col(l));
      if (!(compliance > 0.0)) return false;
      out.stiffness[ll] = total_[ll] * total_[ll] / compliance;
      // d log S / d knob = uᵀ (∂K / ∂knob) u / (fᵀ u).
      std::array<double, kKnobs> energy{};
      for (std::size_t s = 0; s < box_.linearSprings.size(); ++s) {
        const Family f = beam_.family[s];
        if (f != kAxial && f != kLongDiagonal) continue;
        const auto [a, b] = ends(s);
        const double stretch = dot(direction(s), displacement(U, l, a) - displacement(U, l, b));
        const double e = stretch * stretch;
        if (f == kLongDiagonal) {
          energy[1] += stiffness(s, knobs) * e;
        } else {
          energy[0] += stiffness(s, knobs) * e;
          energy[3] += base_[s] * knobs.axial * beam_.tilt[s] * e;
        }
      }
      for (const auto& t : beam_.bends) {
        const Vec3 g = (displacement(U, l, static_cast<std::size_t>(t[0])) -
                        displacement(U, l, static_cast<std::size_t>(t[1])) * 2.0 +
                        displacement(U, l, static_cast<std::size_t>(t[2]))) /
                       beam_.a;
        const double y = component(g, beam_.across[0]), z = component(g, beam_.across[1]);
        energy[2] += bendUnit_ * (y * y + z * z);
      }
      for (std::size_t j = 0; j < kKnobs; ++j) out.dLog[ll][j] = energy[j] / compliance;
    }
    return true;
  }

 private:
  void assemble(const Knobs& knobs, BandCholesky& matrix) const {
    // Adds v·M to the 3×3 block (p, q), lower triangle only.
    const auto add = [&](std::size_t p, std::size_t q, double v, const double m[3][3]) {
      if (dof_[p] < 0 || dof_[q] < 0) return;
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          const Eigen::Index i = dof_[p] + r, j = dof_[q] + c;
          if (i >= j && m[r][c] != 0.0) matrix.add(i, j, v * m[r][c]);
        }
      }
    };
    for (std::size_t s = 0; s < box_.linearSprings.size(); ++s) {
      const double k = stiffness(s, knobs);
      if (k == 0.0) continue;
      const auto [a, b] = ends(s);
      const Vec3 u = direction(s);
      const double e[3] = {u.x, u.y, u.z};
      double nn[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) nn[r][c] = e[r] * e[c];
      add(a, a, k, nn);
      add(b, b, k, nn);
      add(a, b, -k, nn);
      add(b, a, -k, nn);
    }
    const double kb = knobs.bend * bendUnit_;
    if (kb > 0.0) {
      const double c[3] = {1.0 / beam_.a, -2.0 / beam_.a, 1.0 / beam_.a};
      double normal[3][3] = {};
      for (int across : beam_.across) normal[across][across] = 1.0;
      for (const auto& t : beam_.bends) {
        for (std::size_t i = 0; i < 3; ++i) {
          for (std::size_t j = 0; j < 3; ++j) {
            add(static_cast<std::size_t>(t[i]), static_cast<std::size_t>(t[j]), kb * c[i] * c[j],
                normal);
          }
        }
      }
    }
  }

  std::pair<std::size_t, std::size_t> ends(std::size_t s) const {
    return {static_cast<std::size_t>(box_.linearSprings[s].a),
            static_cast<std::size_t>(box_.linearSprings[s].b)};
  }
  Vec3 direction(std::size_t s) const {
    const auto [a, b] = ends(s);
    const Vec3 d = box_.position[b] - box_.position[a];
    return d / norm(d);
  }
  Vec3 displacement(const Eigen::MatrixXd& U, int load, std::size_t p) const {
    const Eigen::Index d = dof_[p];
    if (d < 0) return Vec3{};
    return Vec3{U(d, load), U(d + 1, load), U(d + 2, load)};
  }

  const GeneratedObject& box_;
  const BeamLattice& beam_;
  std::vector<double> base_;  // per LS: bulk stiffness (N/m)
  double bendUnit_;           // E a³ / 12 (N·m/rad)
  std::vector<Eigen::Index> dof_;
  Eigen::Index size_ = 0, width_ = 0;
  Eigen::MatrixXd loads_;
  std::array<double, kLoads> total_{1.0, 1.0, 1.0, 0.0};  // total force (N) or torque (N·m)
};

// E·A/L, 3·E·I/L³ for both bending planes, G·J/L; L = (n − 1) a and the
// section is the bar's outer hy × hz.
std::array<double, kLoads> beamTargets(const BeamLattice& beam, double E, double G) {
  const double L = (beam.count[0] - 1) * beam.a;
  const double hy = beam.count[1] * beam.a, hz = beam.count[2] * beam.a;
  return {E * hy * hz / L, 3.0 * E * (hz * hy * hy * hy / 12.0) / (L * L * L),
          3.0 * E * (hy * hz * hz * hz / 12.0) / (L * L * L), G * torsionConstant(hy, hz) / L};
}

// 0.2·sqrt(κ m_min / 2) per LS, the generators' rule (resolveSprings).
void setLinearDamping(GeneratedObject& box) {
  const double minMass = *std::min_element(box.mass.begin(), box.mass.end());
  for (LinearSpring& s : box.linearSprings)
    s.damping = 0.2 * std::sqrt(s.stiffness * minMass / 2.0);
}

constexpr const char* kLatticeSpec = "calibrateLattice";

// "a×b×c".
std::string cellText(const std::array<int, 3>& cells) {
  return std::to_string(cells[0]) + "×" + std::to_string(cells[1]) + "×" + std::to_string(cells[2]);
}

void calibrateBeam(GeneratedObject& box, const std::array<int, 3>& cells, double a, int axis,
                   double E, double G, double k1, double k2) {
  BeamLattice beam;
  if (!describeBeam(box, cells, a, axis, beam))
    check::fail(kLatticeSpec, "youngModulus",
                "'youngModulus': the particles are not a full box lattice");
  if (beam.count[1] < 2 || beam.count[2] < 2)
    check::fail(kLatticeSpec, "cells",
                "'youngModulus' on a bar needs at least 2 cells across it, got [" +
                    std::to_string(cells[0]) + ", " + std::to_string(cells[1]) + ", " +
                    std::to_string(cells[2]) +
                    "]: a single row or layer of particles has no torsional stiffness");
  std::vector<double> base;
  for (Family f : beam.family)
    base.push_back(f == kAxial || f == kTransverse ? k1 : (f == kBodyDiagonal ? 0.0 : k2));
  const double bendUnit = E * a * a * a / 12.0;
  const BeamStatics statics(box, beam, base, bendUnit);
  if (statics.work() > kMaxWork || statics.memory() > kMaxBand)
    check::fail(kLatticeSpec, "cells",
                "'youngModulus': a " + cellText(cells) +
                    " bar is too large to calibrate (the cost grows as its length times the cube "
                    "of its section, " +
                    std::to_string(beam.count[1] * beam.count[2]) + " cells); use fewer cells");
  const std::array<double, kLoads> target = beamTargets(beam, E, G);

  // Residuals: log(measured / target) of traction, flexion (mean of the two
  // planes), torsion and, for a rectangle, the flexions' log ratio; unknowns:
  // log axial, log diagonal, bend and, for a rectangle, tilt.
  const bool square = beam.count[1] == beam.count[2];
  const int unknowns = square ? 3 : 4;
  Knobs knobs;
  Response response;
  bool converged = false;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    if (!statics.solve(knobs, response)) break;
    std::array<double, kLoads> logRatio{};
    for (std::size_t l = 0; l < kLoads; ++l)
      logRatio[l] = std::log(response.stiffness[l] / target[l]);
    Eigen::Vector4d res(logRatio[0], 0.5 * (logRatio[1] + logRatio[2]), logRatio[3],
                        logRatio[1] - logRatio[2]);
    Eigen::Matrix4d J;
    for (std::size_t j = 0; j < kKnobs; ++j) {
      const auto& d = response.dLog;
      const auto c = static_cast<Eigen::Index>(j);
      J(0, c) = d[0][j];
      J(1, c) = 0.5 * (d[1][j] + d[2][j]);
      J(2, c) = d[3][j];
      J(3, c) = d[1][j] - d[2][j];
    }
    if (res.head(unknowns).cwiseAbs().maxCoeff() < kTolerance) {
      converged = true;
      break;
    }
    Eigen::Vector4d step = Eigen::Vector4d::Zero();
    step.head(unknowns) =
        J.topLeftCorner(unknowns, unknowns).fullPivLu().solve(-res.head(unknowns));
    if (!step.allFinite()) break;
    // The scales move in log, at most ×/÷ e per step; the TS stay >= 0.
    const double longest = std::max(std::abs(step(0)), std::abs(step(1)));
    if (longest > 1.0) step *= 1.0 / longest;
    knobs.axial *= std::exp(step(0));
    knobs.diagonal *= std::exp(step(1));
    knobs.bend = std::max(0.0, knobs.bend + step(2));
    knobs.tilt += step(3);
  }
  double minAxial = knobs.axial;
  for (std::size_t s = 0; s < box.linearSprings.size(); ++s)
    if (beam.family[s] == kAxial) minAxial = std::min(minAxial, statics.stiffness(s, knobs));
  if (!converged || !(minAxial > 0.0)) {
    std::array<double, kLoads> ratio{};
    for (std::size_t l = 0; l < kLoads; ++l) ratio[l] = response.stiffness[l] / target[l];
    char reached[160];
    std::snprintf(reached, sizeof reached, "traction %.3f, flexion %.3f and %.3f, torsion %.3f",
                  ratio[0], ratio[1], ratio[2], ratio[3]);
    check::fail(kLatticeSpec, "youngModulus",
                "cannot calibrate the " + cellText(cells) + " bar to E = " + check::number(E) +
                    " Pa, G = " + check::number(G) + " Pa: its lattice reaches " + reached +
                    " of E·A/L, 3·E·I/L³, G·J/L" +
                    (minAxial > 0.0 ? "" : " only with negative axial springs"));
  }
  for (std::size_t s = 0; s < box.linearSprings.size(); ++s)
    box.linearSprings[s].stiffness = statics.stiffness(s, knobs);
  setLinearDamping(box);
  // The calibrated TS replace any TS along lattice lines (bendStiffness).
  box.torsionSprings.clear();
  if (knobs.bend > 0.0) {
    const double stiffness = knobs.bend * bendUnit;
    const double minMass = *std::min_element(box.mass.begin(), box.mass.end());
    const double damping = 0.2 * std::sqrt(stiffness * minMass * a * a / 2.0);
    for (const auto& t : beam.bends)
      box.torsionSprings.push_back(
          TorsionSpring{t[0], t[1], t[2], std::numbers::pi, stiffness, damping});
  }
}

}  // namespace

void calibrateLattice(GeneratedObject& box, const BoxSpec& spec, double youngModulus,
                      std::optional<double> shearModulus) {
  check::positive(kLatticeSpec, "youngModulus", youngModulus, "Pa");
  if (shearModulus) check::positive(kLatticeSpec, "shearModulus", *shearModulus, "Pa");
  const Vec3& size = spec.size;
  const std::array<int, 3>& cells = spec.cells;
  for (int c : cells) check::atLeast(kLatticeSpec, "cells", c, 1);
  if (box.size() != static_cast<std::size_t>(cells[0]) * cells[1] * cells[2] ||
      box.linearSprings.empty())
    check::fail(kLatticeSpec, "youngModulus",
                "'youngModulus': the particles are not a full box lattice of " + cellText(cells) +
                    " cells");
  const double a = size.x / cells[0];
  if (!(a > 0.0) || std::abs(size.y / cells[1] - a) > 1e-9 * a ||
      std::abs(size.z / cells[2] - a) > 1e-9 * a)
    check::fail(kLatticeSpec, "youngModulus",
                "'youngModulus' needs cubic cells (size / cells equal in x, y and z)");
  const double E = youngModulus;
  const double G = shearModulus.value_or(0.4 * E);
  // Bulk: k2 = G a, and k1 the positive root of (k1 + k2)(k1 + 4 k2) = E a (k1 + 3 k2),
  // which is > 0 if and only if G < 0.75 E.
  const double k2 = G * a;
  const double b = 5.0 * k2 - E * a, c = 4.0 * k2 * k2 - 3.0 * E * a * k2;
  const double k1 = 0.5 * (-b + std::sqrt(b * b - 4.0 * c));
  if (!(k1 > 0.0))
    check::fail(kLatticeSpec, "shearModulus",
                "'shearModulus' " + check::number(G) + " Pa is too large for 'youngModulus' " +
                    check::number(E) + " Pa: a cubic lattice of central springs needs G < 0.75 E");
  // A slender box is a beam along its longest side.
  const int axis = static_cast<int>(std::max_element(cells.begin(), cells.end()) - cells.begin());
  const int width = std::max(cells[(axis + 1) % 3], cells[(axis + 2) % 3]);
  if (cells[axis] - 1 >= kMinSlenderness * width) {
    calibrateBeam(box, cells, a, axis, E, G, k1, k2);
    return;
  }
  for (LinearSpring& s : box.linearSprings) {
    const double ratio = s.restLength / a;
    s.stiffness = ratio < 1.2 ? k1 : (ratio < 1.6 ? k2 : 0.0);
  }
  setLinearDamping(box);
}

}  // namespace robophi::build
