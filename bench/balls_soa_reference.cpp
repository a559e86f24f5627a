// The yardstick of STEP-SCALING's contacts family (apps/robophi/bench_pile.cpp,
// runStepScaling): the plainest structure-of-arrays DEM loop over the same
// touching balls (pile::scalingCentres, no gravity), with the same contact law
// (linear spring-dashpot, Coulomb friction on a tangential spring, spin) and
// the same timing protocol, on a LAMMPS-style half neighbour list with a skin.
// No energy account, no stages, one thread. robophi's cost per particle-step
// and its highest / lowest ratio are compared with this program's.
//
//   build/robophi_balls_reference          the sweep 1e3, 1e4, 1e5, 1e6
//   build/robophi_balls_reference 100000   one count only
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>
#include <vector>

#include "pile_layout.h"

namespace pile = robophi::cli::pile;

namespace {

constexpr double kR = pile::kRadius, kMass = pile::kScalingMass;
constexpr double kInertia = 0.4 * kMass * kR * kR;  // solid ball
constexpr double kDt = 1.0e-5;
// Two equal materials (κ 1e4 N/m, c 10 N·s/m) in series.
constexpr double kKn = 5.0e3, kCn = 5.0;
constexpr double kKt = kKn, kCt = kCn;
constexpr double kMuS = 0.5, kMuK = 0.4;
// The list keeps every pair closer than 2r + skin; it stays exact until some
// ball has moved skin / 2 (two balls closing on each other use the whole skin).
constexpr double kSkin = 0.5 * kR;
constexpr double kCutoff = 2.0 * kR + kSkin;

// The tangential spring of one list entry (m); zero while the pair is apart.
struct Shear {
  double x = 0.0, y = 0.0, z = 0.0;
};

// Everything a step reads and writes, so that one copy is a snapshot.
struct Balls {
  int count = 0;
  std::vector<double> x, y, z, vx, vy, vz, wx, wy, wz;  // m, m/s, rad/s
  std::vector<double> fx, fy, fz, tx, ty, tz;           // N, N·m
  // Half neighbour list (j > i) in CSR form: row i is partner[start[i]..start[i+1]).
  std::vector<std::size_t> start;
  std::vector<int> partner;
  std::vector<Shear> shear;        // parallel to partner
  std::vector<double> x0, y0, z0;  // the positions at the list's build
  bool stale = true;
};

// The build's work arrays, kept between builds so a rebuild does not allocate.
struct Grid {
  std::vector<int> cellOf, cellStart, order;
  std::vector<std::size_t> start;
  std::vector<int> partner;
  std::vector<Shear> shear;
};

// Bins the balls into cells of side kCutoff over their bounding box and lists
// every pair j > i closer than kCutoff; each pair already in the old list keeps
// its tangential spring (found in old row i, a handful of entries).
void buildList(Balls& b, Grid& g) {
  const int n = b.count;
  double lo[3] = {b.x[0], b.y[0], b.z[0]}, hi[3] = {b.x[0], b.y[0], b.z[0]};
  for (int i = 0; i < n; ++i) {
    lo[0] = std::min(lo[0], b.x[i]), hi[0] = std::max(hi[0], b.x[i]);
    lo[1] = std::min(lo[1], b.y[i]), hi[1] = std::max(hi[1], b.y[i]);
    lo[2] = std::min(lo[2], b.z[i]), hi[2] = std::max(hi[2], b.z[i]);
  }
  int dims[3];
  for (int a = 0; a < 3; ++a) dims[a] = static_cast<int>((hi[a] - lo[a]) / kCutoff) + 1;
  const int cells = dims[0] * dims[1] * dims[2];
  auto cellAxis = [&](double p, int a) {
    return std::min(static_cast<int>((p - lo[a]) / kCutoff), dims[a] - 1);
  };
  // Counting sort by cell; a cell's balls stay in index order.
  g.cellOf.resize(static_cast<std::size_t>(n));
  g.order.resize(static_cast<std::size_t>(n));
  g.cellStart.assign(static_cast<std::size_t>(cells) + 1, 0);
  for (int i = 0; i < n; ++i) {
    g.cellOf[i] =
        (cellAxis(b.z[i], 2) * dims[1] + cellAxis(b.y[i], 1)) * dims[0] + cellAxis(b.x[i], 0);
    ++g.cellStart[g.cellOf[i] + 1];
  }
  for (int c = 0; c < cells; ++c) g.cellStart[c + 1] += g.cellStart[c];
  for (int i = 0; i < n; ++i) g.order[g.cellStart[g.cellOf[i]]++] = i;
  for (int c = cells; c > 0; --c) g.cellStart[c] = g.cellStart[c - 1];
  g.cellStart[0] = 0;

  const bool carry = b.start.size() == static_cast<std::size_t>(n) + 1;
  g.start.resize(static_cast<std::size_t>(n) + 1);
  g.partner.clear();
  g.shear.clear();
  for (int i = 0; i < n; ++i) {
    g.start[i] = g.partner.size();
    const int c = g.cellOf[i];
    const int cx = c % dims[0], cy = (c / dims[0]) % dims[1], cz = c / (dims[0] * dims[1]);
    for (int kz = std::max(cz - 1, 0); kz <= std::min(cz + 1, dims[2] - 1); ++kz)
      for (int ky = std::max(cy - 1, 0); ky <= std::min(cy + 1, dims[1] - 1); ++ky)
        for (int kx = std::max(cx - 1, 0); kx <= std::min(cx + 1, dims[0] - 1); ++kx) {
          const int cell = (kz * dims[1] + ky) * dims[0] + kx;
          for (int s = g.cellStart[cell]; s < g.cellStart[cell + 1]; ++s) {
            const int j = g.order[s];
            if (j <= i) continue;
            const double dx = b.x[i] - b.x[j], dy = b.y[i] - b.y[j], dz = b.z[i] - b.z[j];
            if (dx * dx + dy * dy + dz * dz >= kCutoff * kCutoff) continue;
            Shear kept;
            for (std::size_t k = carry ? b.start[i] : 0; carry && k < b.start[i + 1]; ++k)
              if (b.partner[k] == j) {
                kept = b.shear[k];
                break;
              }
            g.partner.push_back(j);
            g.shear.push_back(kept);
          }
        }
  }
  g.start[n] = g.partner.size();
  std::swap(b.start, g.start);
  std::swap(b.partner, g.partner);
  std::swap(b.shear, g.shear);
  b.x0 = b.x;
  b.y0 = b.y;
  b.z0 = b.z;
  b.stale = false;
}

void step(Balls& b, Grid& g) {
  if (b.stale) buildList(b, g);
  const int n = b.count;
  for (int i = 0; i < n; ++i) {
    b.fx[i] = b.fy[i] = b.fz[i] = 0.0;
    b.tx[i] = b.ty[i] = b.tz[i] = 0.0;
  }
  for (int i = 0; i < n; ++i) {
    for (std::size_t k = b.start[i]; k < b.start[i + 1]; ++k) {
      const int j = b.partner[k];
      Shear& h = b.shear[k];
      const double dx = b.x[i] - b.x[j], dy = b.y[i] - b.y[j], dz = b.z[i] - b.z[j];
      const double dist2 = dx * dx + dy * dy + dz * dz;
      if (dist2 >= 4.0 * kR * kR) {
        h = Shear{};  // apart: the contact's history ends
        continue;
      }
      const double dist = std::sqrt(dist2), inv = 1.0 / dist;
      const double nx = dx * inv, ny = dy * inv, nz = dz * inv;
      const double depth = dist - 2.0 * kR;  // < 0
      const double rvx = b.vx[i] - b.vx[j], rvy = b.vy[i] - b.vy[j], rvz = b.vz[i] - b.vz[j];
      const double fn = std::max(0.0, -kKn * depth - kCn * (rvx * nx + rvy * ny + rvz * nz));
      // Contact point velocity: arms a_i = -n L, a_j = n L, so the spins add
      // -L (w_i + w_j) × n.
      const double arm = kR + 0.5 * depth;
      const double sx = b.wx[i] + b.wx[j], sy = b.wy[i] + b.wy[j], sz = b.wz[i] + b.wz[j];
      const double cx = rvx - arm * (sy * nz - sz * ny);
      const double cy = rvy - arm * (sz * nx - sx * nz);
      const double cz = rvz - arm * (sx * ny - sy * nx);
      const double cn = cx * nx + cy * ny + cz * nz;
      const double vtx = cx - cn * nx, vty = cy - cn * ny, vtz = cz - cn * nz;
      // The spring stretches with the slip and stays in the (turning) tangent plane.
      h.x += vtx * kDt;
      h.y += vty * kDt;
      h.z += vtz * kDt;
      const double hn = h.x * nx + h.y * ny + h.z * nz;
      h.x -= hn * nx;
      h.y -= hn * ny;
      h.z -= hn * nz;
      double ftx = -kKt * h.x - kCt * vtx, fty = -kKt * h.y - kCt * vty,
             ftz = -kKt * h.z - kCt * vtz;
      const double ft2 = ftx * ftx + fty * fty + ftz * ftz;
      if (ft2 > kMuS * kMuS * fn * fn) {
        // Sliding: kinetic friction, and the spring holds just that force.
        const double scale = kMuK * fn / std::sqrt(ft2);
        ftx *= scale, fty *= scale, ftz *= scale;
        h.x = -(ftx + kCt * vtx) / kKt;
        h.y = -(fty + kCt * vty) / kKt;
        h.z = -(ftz + kCt * vtz) / kKt;
      }
      const double fx = fn * nx + ftx, fy = fn * ny + fty, fz = fn * nz + ftz;
      b.fx[i] += fx, b.fy[i] += fy, b.fz[i] += fz;
      b.fx[j] -= fx, b.fy[j] -= fy, b.fz[j] -= fz;
      // a_i × F_t = a_j × (-F_t) = -L n × F_t.
      const double qx = -arm * (ny * ftz - nz * fty), qy = -arm * (nz * ftx - nx * ftz),
                   qz = -arm * (nx * fty - ny * ftx);
      b.tx[i] += qx, b.ty[i] += qy, b.tz[i] += qz;
      b.tx[j] += qx, b.ty[j] += qy, b.tz[j] += qz;
    }
  }
  // Symplectic Euler; a ball that has moved skin / 2 since the build asks for a new list.
  const double limit2 = 0.25 * kSkin * kSkin;
  for (int i = 0; i < n; ++i) {
    b.vx[i] += b.fx[i] / kMass * kDt;
    b.vy[i] += b.fy[i] / kMass * kDt;
    b.vz[i] += b.fz[i] / kMass * kDt;
    b.wx[i] += b.tx[i] / kInertia * kDt;
    b.wy[i] += b.ty[i] / kInertia * kDt;
    b.wz[i] += b.tz[i] / kInertia * kDt;
    b.x[i] += b.vx[i] * kDt;
    b.y[i] += b.vy[i] * kDt;
    b.z[i] += b.vz[i] * kDt;
    const double mx = b.x[i] - b.x0[i], my = b.y[i] - b.y0[i], mz = b.z[i] - b.z0[i];
    if (mx * mx + my * my + mz * mz > limit2) b.stale = true;
  }
}

// Touching pairs (the list holds them all while it is fresh).
std::size_t touching(const Balls& b) {
  std::size_t out = 0;
  for (int i = 0; i < b.count; ++i)
    for (std::size_t k = b.start[i]; k < b.start[i + 1]; ++k) {
      const int j = b.partner[k];
      const double dx = b.x[i] - b.x[j], dy = b.y[i] - b.y[j], dz = b.z[i] - b.z[j];
      if (dx * dx + dy * dy + dz * dz < 4.0 * kR * kR) ++out;
    }
  return out;
}

Balls makeBalls(long long count) {
  Balls b;
  b.count = static_cast<int>(count);
  const auto n = static_cast<std::size_t>(count);
  for (auto* v : {&b.x, &b.y, &b.z, &b.vx, &b.vy, &b.vz, &b.wx, &b.wy, &b.wz, &b.fx, &b.fy, &b.fz,
                  &b.tx, &b.ty, &b.tz})
    v->assign(n, 0.0);
  std::size_t i = 0;
  for (const auto& [px, py, pz] : pile::scalingCentres(count)) {
    b.x[i] = px;
    b.y[i] = py;
    b.z[i] = pz;
    ++i;
  }
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<long long> counts = {1000, 10000, 100000, 1000000};
  if (argc > 1) counts = {std::atoll(argv[1])};
  if (counts[0] < 2) {
    std::fprintf(stderr, "usage: %s [count >= 2]\n", argv[0]);
    return 1;
  }
  double lowest = 0.0, highest = 0.0;
  for (const long long count : counts) {
    Balls balls = makeBalls(count);
    Grid grid;
    // Warm-up as robophi's: the list is built and the contacts settle in.
    for (int warm = 0; warm < 16; ++warm) step(balls, grid);
    // Rounds of 10 steps from the same state (the cloud spreads out, so a long
    // run would measure a sparser one); the restores are not timed.
    const Balls snapshot = balls;
    constexpr long long kRound = 10;
    const long long rounds = std::max(1LL, 10000000LL / (kRound * count));
    const long long steps = rounds * kRound;
    double seconds = 0.0;
    for (long long r = 0; r < rounds; ++r) {
      balls = snapshot;
      const auto begin = std::chrono::steady_clock::now();
      for (long long k = 0; k < kRound; ++k) step(balls, grid);
      seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    }
    const double perParticleStep =
        seconds / (static_cast<double>(steps) * static_cast<double>(count));
    lowest = lowest == 0.0 ? perParticleStep : std::min(lowest, perParticleStep);
    highest = std::max(highest, perParticleStep);
    std::printf(
        "BALLS-SOA particles=%-8lld steps=%-6lld wall_s=%-8.3f ns_per_particle_step=%-7.2f "
        "contacts=%-8zu\n",
        count, steps, seconds, 1e9 * perParticleStep, touching(balls));
    std::fflush(stdout);
  }
  if (counts.size() > 1)
    std::printf("BALLS-SOA cost per particle-step, highest / lowest (1e3..1e6) = %.3f\n",
                highest / lowest);
  return 0;
}
