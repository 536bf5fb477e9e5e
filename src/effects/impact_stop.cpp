#include "vehs/effects/impact_stop.hpp"

#include <algorithm>
#include <vector>

namespace vehs::effects {

namespace {

/// ∫₀¹ z⁺ du and ∫₀¹ u·z⁺ du for z(u) = a + d·u.
inline void hinge_moments(double a, double d, double& m0, double& m1) {
  double u1 = 0.0, u2 = 1.0;
  if (d == 0.0) {
    m0 = std::max(a, 0.0);
    m1 = 0.5 * m0;
    return;
  }
  const double root = -a / d;
  if (d > 0) u1 = std::clamp(root, 0.0, 1.0);
  else u2 = std::clamp(root, 0.0, 1.0);
  if (u2 <= u1) {
    m0 = m1 = 0.0;
    return;
  }
  m0 = a * (u2 - u1) + 0.5 * d * (u2 * u2 - u1 * u1);
  m1 = 0.5 * a * (u2 * u2 - u1 * u1) + d * (u2 * u2 * u2 - u1 * u1 * u1) / 3.0;
}

}  // namespace

void impact_stop_record_shape(const double* x, std::size_t n, double gp, double gn, int tent_k, double* out) {
  const auto k = static_cast<std::size_t>(std::max(tent_k, 0));
  for (std::size_t i = 0; i < n; ++i) {
    if (k == 0 || i < k || i + k >= n) {
      out[i] = ImpactStop<double>{1.0, gp, gn}.force(x[i]);
      continue;
    }
    // quick exit: the whole window inside the gaps
    double lo = x[i], hi = x[i];
    for (std::size_t j = i - k; j <= i + k; ++j) lo = std::min(lo, x[j]), hi = std::max(hi, x[j]);
    if (hi <= gp && lo >= -gn) {
      out[i] = 0.0;
      continue;
    }
    const double kk = static_cast<double>(k) * static_cast<double>(k);
    double acc = 0.0;
    for (long j = -static_cast<long>(k); j < static_cast<long>(k); ++j) {
      const double xa = x[static_cast<std::size_t>(static_cast<long>(i) + j)];
      const double xb = x[static_cast<std::size_t>(static_cast<long>(i) + j + 1)];
      const double alpha = j >= 0 ? (static_cast<double>(k) - static_cast<double>(j)) / kk
                                  : (static_cast<double>(k) + static_cast<double>(j)) / kk;
      const double beta = j >= 0 ? -1.0 / kk : 1.0 / kk;
      double m0, m1;
      hinge_moments(xa - gp, xb - xa, m0, m1);
      acc -= alpha * m0 + beta * m1;
      hinge_moments(-xa - gn, -(xb - xa), m0, m1);
      acc += alpha * m0 + beta * m1;
    }
    out[i] = acc;
  }
}

void add_impact_stop_record_force(const ImpactStop<double>& stop, const double* x, std::size_t n, int tent_k,
                                  double* out) {
  std::vector<double> shape(n);
  impact_stop_record_shape(x, n, stop.gap, stop.gap_neg, tent_k, shape.data());
  for (std::size_t i = 0; i < n; ++i) out[i] += stop.k_stop * shape[i];
}

}  // namespace vehs::effects
