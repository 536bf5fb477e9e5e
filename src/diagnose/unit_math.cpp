#include "unit_math.hpp"

#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"

namespace vehs::diagnose::detail {

std::string fmt(double v, int digits) { return vehs::detail::format_number(v, digits); }

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

Ratio ratio_over_units(const std::vector<double>& N, const std::vector<double>& D) {
  const double sn = std::accumulate(N.begin(), N.end(), 0.0), sd = std::accumulate(D.begin(), D.end(), 0.0);
  Ratio r;
  if (!(sd > 0.0)) return r;
  r.value = sn / sd;
  const double U = static_cast<double>(N.size());
  if (U < 2) return r;
  double ss = 0.0;
  for (std::size_t j = 0; j < N.size(); ++j) ss += (N[j] - r.value * D[j]) * (N[j] - r.value * D[j]);
  r.se = std::sqrt(U / (U - 1.0) * ss) / sd;
  return r;
}

Ratio mean_over_units(const std::vector<double>& v) {
  Ratio r;
  double s = 0.0, n = 0.0;
  for (double x : v)
    if (std::isfinite(x)) s += x, n += 1.0;
  if (n == 0) return r;
  r.value = s / n;
  if (n < 2) return r;
  double ss = 0.0;
  for (double x : v)
    if (std::isfinite(x)) ss += (x - r.value) * (x - r.value);
  r.se = std::sqrt(ss / (n - 1.0) / n);
  return r;
}

std::vector<std::size_t> log_bands(std::size_t kmax, int nb) {
  std::vector<std::size_t> e{1};
  for (int b = 1; b <= nb; ++b) {
    const auto k = static_cast<std::size_t>(
        std::llround(std::exp(std::log(static_cast<double>(kmax + 1)) * b / nb)));
    if (k > e.back()) e.push_back(std::min(k, kmax + 1));
  }
  if (e.back() != kmax + 1) e.push_back(kmax + 1);
  return e;
}

double band_mean(const std::vector<double>& psd, std::size_t a, std::size_t b) {
  double s = 0.0;
  for (std::size_t k = a; k < b; ++k) s += psd[k];
  return s / static_cast<double>(b - a);
}

double mean_log_band(const std::vector<std::vector<double>>& each, std::size_t a, std::size_t b) {
  if (each.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (const auto& psd : each) {
    const double v = band_mean(psd, a, b);
    if (!(v > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    sum += std::log(v);
  }
  return sum / static_cast<double>(each.size());
}

double mean_of(const std::vector<double>& v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (double e : v) sum += e;
  return sum / static_cast<double>(v.size());
}

}  // namespace vehs::diagnose::detail
