// The yardstick of the CLOTH benchmark: the plainest structure-of-arrays loop
// over springs (no energy account, no stages), same scene, same integrator.
// robophi's CLOTH figure is compared with this program's on the same machine.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 128;
  const double duration = argc > 2 ? std::atof(argv[2]) : 1.0;
  const double spacing = 0.01, stiffness = 1.0e4, g = 9.81;
  const int count = n * n;
  const double mass = 1.0 / count;
  const double damping = 0.2 * std::sqrt(stiffness * mass);
  const double dt = 1.0e-4 * 32.0 / n;
  std::vector<double> x(count), y(count), z(count, 0.0), vx(count, 0.0), vy(count, 0.0),
      vz(count, 0.0), fx(count), fy(count), fz(count), invMass(count, 1.0 / mass);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      x[j * n + i] = i * spacing;
      y[j * n + i] = j * spacing;
    }
  invMass[0] = invMass[n - 1] = 0.0;
  std::vector<int> sa, sb;
  std::vector<double> rest;
  auto spring = [&](int a, int b, double r) {
    sa.push_back(a);
    sb.push_back(b);
    rest.push_back(r);
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i + 1 < n) spring(j * n + i, j * n + i + 1, spacing);
      if (j + 1 < n) spring(j * n + i, (j + 1) * n + i, spacing);
      if (i + 1 < n && j + 1 < n) {
        spring(j * n + i, (j + 1) * n + i + 1, std::sqrt(2.0) * spacing);
        spring(j * n + i + 1, (j + 1) * n + i, std::sqrt(2.0) * spacing);
      }
    }
  const long steps = static_cast<long>(std::ceil(duration / dt - 1e-9));
  const auto start = std::chrono::steady_clock::now();
  for (long s = 0; s < steps; ++s) {
    for (int i = 0; i < count; ++i) {
      fx[i] = 0.0;
      fy[i] = 0.0;
      fz[i] = -g * mass;
    }
    const std::size_t springs = rest.size();
    for (std::size_t k = 0; k < springs; ++k) {
      const int a = sa[k], b = sb[k];
      const double dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
      const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
      const double inv = 1.0 / length;
      const double ux = dx * inv, uy = dy * inv, uz = dz * inv;
      const double rate = (vx[a] - vx[b]) * ux + (vy[a] - vy[b]) * uy + (vz[a] - vz[b]) * uz;
      const double f = -stiffness * (length - rest[k]) - damping * rate;
      fx[a] += f * ux;
      fy[a] += f * uy;
      fz[a] += f * uz;
      fx[b] -= f * ux;
      fy[b] -= f * uy;
      fz[b] -= f * uz;
    }
    for (int i = 0; i < count; ++i) {
      vx[i] += fx[i] * invMass[i] * dt;
      vy[i] += fy[i] * invMass[i] * dt;
      vz[i] += fz[i] * invMass[i] * dt;
      x[i] += vx[i] * dt;
      y[i] += vy[i] * dt;
      z[i] += vz[i] * dt;
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "CLOTH-%d reference SoA loop: steps=%ld wall_s=%.3f particle_steps_per_s=%.3e "
      "(z of the last particle %.6f)\n",
      n, steps, wall, static_cast<double>(count) * static_cast<double>(steps) / wall, z[count - 1]);
  return 0;
}
