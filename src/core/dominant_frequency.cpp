#include "vehs/core/dominant_frequency.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vehs {

double dominant_omega_dt(const Dataset& data) {
  double var = 0.0, d1 = 0.0, d2 = 0.0;
  std::size_t n = 0, n1 = 0, n2 = 0;
  for (const auto& rec : data.records) {
    if (rec.size < 3) continue;
    const double* x = data.x_of(rec);
    double mean = 0.0;
    for (std::size_t i = 0; i < rec.size; ++i) mean += x[i];
    mean /= static_cast<double>(rec.size);
    for (std::size_t i = 0; i < rec.size; ++i) var += (x[i] - mean) * (x[i] - mean);
    for (std::size_t i = 1; i < rec.size; ++i) d1 += (x[i] - x[i - 1]) * (x[i] - x[i - 1]);
    for (std::size_t i = 2; i < rec.size; ++i) d2 += (x[i] - x[i - 2]) * (x[i] - x[i - 2]);
    n += rec.size;
    n1 += rec.size - 1;
    n2 += rec.size - 2;
  }
  if (n2 == 0 || !(var > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  var /= static_cast<double>(n);
  d1 /= static_cast<double>(n1);
  d2 /= static_cast<double>(n2);
  // q (3 − 4q) = r with q = sin²(ω̂Δt/2); beyond r = 9/16 (ω̂Δt ≈ 1.82) the lag-2 contrast
  // turns over: report that edge
  const double r = std::clamp((d2 - d1) / (4.0 * var), 0.0, 9.0 / 16.0);
  const double q = (3.0 - std::sqrt(9.0 - 16.0 * r)) / 8.0;
  return 2.0 * std::asin(std::sqrt(q));
}

}  // namespace vehs
