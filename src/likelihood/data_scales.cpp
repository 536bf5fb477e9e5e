#include "vehs/likelihood/detail/data_scales.hpp"

namespace vehs::likelihood::detail {

double x_variance(const Dataset& data) {
  double mean = 0.0, m2 = 0.0;
  std::size_t n = 0;
  for (double v : data.x) {
    ++n;
    const double d = v - mean;
    mean += d / double(n);
    m2 += d * (v - mean);
  }
  return n > 1 ? m2 / double(n - 1) : 0.0;
}

double mean_squared_rate(const Dataset& data) {
  double sum = 0.0, pairs = 0.0;
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    for (std::size_t k = 0; k + 1 < r.size; ++k) {
      const double d = (x[k + 1] - x[k]) / r.dt;
      sum += d * d;
      pairs += 1.0;
    }
  }
  return pairs > 0.0 ? sum / pairs : 0.0;
}

}  // namespace vehs::likelihood::detail
