#pragma once
// Internal: small statistics over units (ratios with cluster standard errors, means) and the
// log-spaced frequency bands of the spectrum components.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

namespace vehs::diagnose::detail {

std::string fmt(double v, int digits = 4);

/// The q-quantile of v (nth_element: v is reordered).
double quantile(std::vector<double>& v, double q);

inline std::size_t pow2_at_most(std::size_t n) {
  std::size_t p = 1;
  while (p * 2 <= n) p *= 2;
  return p;
}

/// A value with its standard error.
struct Ratio {
  double value = 0.0, se = 0.0;
};
/// ΣN/ΣD over units with its cluster (delta-method jackknife) standard error.
Ratio ratio_over_units(const std::vector<double>& N, const std::vector<double>& D);
/// Mean and standard error over units of per-unit values (skipping NaN).
Ratio mean_over_units(const std::vector<double>& v);

/// Log-spaced bands of frequency indices [1, kmax]: edges e_0 = 1 < … < e_nb = kmax + 1.
std::vector<std::size_t> log_bands(std::size_t kmax, int nb);
/// Mean of psd[a, b).
double band_mean(const std::vector<double>& psd, std::size_t a, std::size_t b);
/// Mean over replicates of log band_mean(psd, a, b) (b = a + 1: one bin); NaN when there is no
/// replicate or a replicate's band is not positive.
double mean_log_band(const std::vector<std::vector<double>>& each, std::size_t a, std::size_t b);
/// Mean of the values (NaN when empty; a non-finite value makes it non-finite).
double mean_of(const std::vector<double>& v);

}  // namespace vehs::diagnose::detail
