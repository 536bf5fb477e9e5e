#pragma once
// Records of a Duffing-type oscillator for the data checks' tests (glitches, flat stretches):
// dX = Y dt, dY = (-x - 0.1 y - x^3) dt + 0.3 dW, Euler-Maruyama on a step 10 times finer than
// the recorded dt (the code under test never sees the generator).
#include <cmath>
#include <random>

#include "vehs/core/dataset.hpp"

namespace core_test {

inline vehs::Dataset oscillator(std::size_t samples, std::uint32_t seed, std::size_t records = 1, double dt = 0.01) {
  vehs::Dataset d;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  const double h = dt / 10;
  for (std::size_t r = 0; r < records; ++r) {
    vehs::Record rec;
    rec.source = "clean.csv";
    rec.id = static_cast<long long>(r);
    rec.first_line = 2 + r * samples;
    rec.dt = dt;
    rec.offset = d.x.size();
    rec.size = samples;
    double x = 0.5, y = 0.0;
    for (std::size_t i = 0; i < samples; ++i) {
      d.x.push_back(x);
      for (int s = 0; s < 10; ++s) {
        const double a = -x - 0.1 * y - x * x * x;
        x += y * h;
        y += a * h + 0.3 * std::sqrt(h) * n01(rng);
      }
    }
    d.records.push_back(rec);
  }
  return d;
}

/// The same records written as integer counts, round(counts_per_unit · x): an ADC's output.
inline vehs::Dataset oscillator_counts(std::size_t samples, std::uint32_t seed, std::size_t records, double dt,
                                       double counts_per_unit) {
  vehs::Dataset d = oscillator(samples, seed, records, dt);
  for (double& x : d.x) x = std::round(counts_per_unit * x);
  return d;
}

}  // namespace core_test
