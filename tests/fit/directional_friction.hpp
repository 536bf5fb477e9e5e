#pragma once
// Records of a rig whose friction differs by direction (Coulomb and viscous per direction, the
// published ball-screw case), in physical units (m, s): Euler–Maruyama on 50 substeps of each
// recorded interval, not vehs's simulator, with white sensor noise.
#include <cmath>
#include <cstdint>
#include <random>

#include "vehs/core/dataset.hpp"

namespace directional {

struct Truth {
  double k = 987.0;               // stiffness per mass, 1/s² (5 Hz)
  double Fp = 0.30, Fm = 0.20;    // Coulomb friction per direction, m/s²
  double cp = 2.0, cm = 5.0;      // viscous damping per direction, 1/s
  double a22 = 6e-3;              // m²/s³
};

inline double force(const Truth& p, double x, double y) {
  const double up = y > 0 ? 1.0 : 0.0, down = y < 0 ? 1.0 : 0.0;
  return -p.k * x - p.Fp * up + p.Fm * down - (p.cp * up + p.cm * down) * y;
}

inline vehs::Dataset directional_friction(std::size_t n, std::uint64_t seed, double dt, double noise_sd) {
  const Truth p;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  const int sub = 50;
  const double h = dt / sub, sq = std::sqrt(p.a22 * h);
  vehs::Dataset d;
  vehs::Record r;
  r.source = "rig.csv";
  r.dt = dt;
  r.size = n;
  double x = 1e-3, y = 0.0;
  for (int i = 0; i < 2000 * sub; ++i) {  // burn-in
    const double a = force(p, x, y);
    x += y * h;
    y += a * h + sq * n01(rng);
  }
  for (std::size_t i = 0; i < n; ++i) {
    d.x.push_back(x + noise_sd * n01(rng));
    for (int s = 0; s < sub; ++s) {
      const double a = force(p, x, y);
      x += y * h;
      y += a * h + sq * n01(rng);
    }
  }
  d.records.push_back(r);
  return d;
}

}  // namespace directional
