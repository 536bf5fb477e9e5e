#include "vehs/likelihood/adequacy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"

namespace vehs::likelihood {

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

SamplingAdequacy assess_sampling(const Model& fit, const Dataset& data) {
  SamplingAdequacy a;
  a.omega_dt = dominant_omega_dt(data);
  a.bias = a.omega_dt * a.omega_dt / 12.0;
  a.best_relative_se = std::numeric_limits<double>::infinity();
  for (const auto& tc : fit.drift) {
    const auto it = fit.drift_stderr.find(tc.term.name());
    if (tc.coef != 0.0 && it != fit.drift_stderr.end() && it->second > 0.0)
      a.best_relative_se = std::min(a.best_relative_se, it->second / std::abs(tc.coef));
  }
  a.recorded_input = fit.uses_drive();
  const auto g = [](double v) { return vehs::detail::format_number(v, 3); };
  if (!std::isfinite(a.omega_dt)) {
    a.reason = "the data's dominant frequency is undefined (constant or too short records)";
    return a;
  }
  const std::string w = "omega*dt = " + g(a.omega_dt);
  if (a.omega_dt >= 0.2 && a.bias > a.best_relative_se) {
    a.vouched = false;
    a.reason = w + ": the expansions' relative bias (omega*dt)^2/12 = " + g(a.bias) +
               " exceeds the best relative standard error " + g(a.best_relative_se);
  } else if (a.recorded_input && a.omega_dt >= 0.1) {
    a.vouched = false;
    a.reason = w + " with a recorded input: holding u over an interval delays it by dt/2, a phase error of " +
               g(a.omega_dt / 2) + " rad";
  } else {
    a.reason = w + ": the expansions in dt hold (bias " + g(a.bias) + " vs best relative SE " +
               g(a.best_relative_se) + ")";
  }
  return a;
}

}  // namespace vehs::likelihood
