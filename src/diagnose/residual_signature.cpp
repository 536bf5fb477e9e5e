// The features of standardised innovations z_k = (x_k − x̂_k)/√S_k that a calibrated filter of
// the right model does not show, each as a z-value against white N(0, 1) innovations:
//   lag-1 autocorrelation ρ₁ (se 1/√n); excess kurtosis (se √(24/n)); corr(z², ŷ²) and
//   corr(z², x̂²) with the filtered state before the sample (se 1/√n); the largest
//   |corr(z_k, u_{k−l})| over lags 0 … 20 (Bonferroni over the lags); the largest ordinate of
//   the periodogram averaged over segments of 256 samples (each ordinate ~ χ²_{2K}/2K under
//   white innovations, Bonferroni over the frequencies).
#include "residual_signature.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <utility>
#include <vector>

#include "unit_math.hpp"
#include "vehs/diagnose/distributions.hpp"

namespace vehs::diagnose {

using detail::fmt;

namespace {

double corr(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= n, mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb);
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

/// z-equivalent Φ⁻¹(1 − p) of a p-value after a Bonferroni correction over m tests.
double bonferroni_z(double p, double m) { return normal_isf(std::clamp(p * m, 1e-300, 0.5)); }

/// Largest averaged periodogram ordinate over segments of `len` samples within pieces.
void spectral_line(const std::vector<std::vector<double>>& pieces, double dt, ResidualSignature& s) {
  const std::size_t len = 256, half = len / 2;
  std::vector<double> power(half, 0.0);
  int segments = 0;
  for (const auto& z : pieces)
    for (std::size_t a = 0; a + len <= z.size(); a += len) {
      for (std::size_t f = 1; f < half; ++f) {
        std::complex<double> c = 0.0;
        for (std::size_t k = 0; k < len; ++k) c += z[a + k] * std::polar(1.0, -2.0 * M_PI * double(f * k) / double(len));
        power[f] += std::norm(c) / double(len);
      }
      ++segments;
    }
  if (segments < 2) return;
  std::size_t best = 1;
  for (std::size_t f = 1; f < half; ++f)
    if (power[f] > power[best]) best = f;
  const double K = segments, stat = 2.0 * power[best];  // ~ χ²_{2K} when each ordinate ~ χ²₂/2
  s.line_frequency = 2.0 * M_PI * double(best) / (double(len) * dt);
  s.line_z = bonferroni_z(chi2_sf(stat, 2.0 * K), double(half - 1));
}

}  // namespace

ResidualSignature residual_signature(const Dataset& held, const likelihood::FilterTrace& tr, double dt) {
  ResidualSignature s;
  std::vector<std::vector<double>> pieces;
  std::vector<double> z, z_prev, z2, y2, x2;
  std::vector<std::vector<double>> u_lag(21);
  for (const auto& r : held.records) {
    std::vector<double> piece;
    for (std::size_t k = r.offset + 1; k < r.offset + r.size; ++k) {
      const double zk = (held.x[k] - tr.predicted_x[k]) / std::sqrt(tr.predicted_var[k]);
      piece.push_back(zk);
      z.push_back(zk);
      z2.push_back(zk * zk);
      y2.push_back(tr.filtered_y[k - 1] * tr.filtered_y[k - 1]);
      x2.push_back(tr.filtered_x[k - 1] * tr.filtered_x[k - 1]);
      if (k > r.offset + 1) z_prev.push_back(z[z.size() - 2]);
      else z_prev.push_back(0.0);
    }
    pieces.push_back(std::move(piece));
  }
  const double n = double(z.size());
  s.samples = z.size();
  if (s.samples < 100) return s;
  double m2 = 0, m4 = 0;
  for (double v : z) m2 += v * v, m4 += v * v * v * v;
  m2 /= n, m4 /= n;
  s.variance = m2;
  s.lag1 = corr(z, z_prev);
  s.lag1_z = s.lag1 * std::sqrt(n);
  s.excess_kurtosis = m4 / (m2 * m2) - 3.0;
  s.kurtosis_z = s.excess_kurtosis / std::sqrt(24.0 / n);
  const double cy = corr(z2, y2), cx = corr(z2, x2);
  const bool vel = std::abs(cy) >= std::abs(cx);
  s.heteroscedasticity = vel ? cy : cx;
  s.heteroscedastic_in = vel ? "velocity" : "displacement";
  // z² has variance 2 + excess kurtosis: the correlation's se is still 1/√n
  s.heteroscedasticity_z = s.heteroscedasticity * std::sqrt(n);
  if (held.has_u()) {
    double best = 0.0;
    for (int lag = 0; lag <= 20; ++lag) {
      std::vector<double> a, b;
      for (const auto& r : held.records)
        for (std::size_t k = r.offset + 1 + std::size_t(lag); k < r.offset + r.size; ++k) {
          a.push_back((held.x[k] - tr.predicted_x[k]) / std::sqrt(tr.predicted_var[k]));
          b.push_back(held.u[k - std::size_t(lag)]);
        }
      if (a.size() < 100) continue;
      const double c = corr(a, b);
      if (std::abs(c) > std::abs(best)) best = c, s.input_lag = lag;
    }
    s.input_correlation = best;
    s.input_z = bonferroni_z(2.0 * normal_sf(std::abs(best) * std::sqrt(n)), 21.0);
  }
  spectral_line(pieces, dt, s);
  // the one-line summary: features beyond 4 standard errors, largest first
  std::vector<std::pair<double, std::string>> f;
  if (std::abs(s.lag1_z) > 4) f.push_back({std::abs(s.lag1_z), "innovations correlated in time (lag-1 " + fmt(s.lag1, 3) + ", z " + fmt(s.lag1_z, 3) + ")"});
  if (s.kurtosis_z > 4) f.push_back({s.kurtosis_z, "heavy-tailed innovations (excess kurtosis " + fmt(s.excess_kurtosis, 3) + ", z " + fmt(s.kurtosis_z, 3) + ")"});
  if (std::abs(s.heteroscedasticity_z) > 4)
    f.push_back({std::abs(s.heteroscedasticity_z), "innovation variance following the " + s.heteroscedastic_in + " (corr " +
                                                        fmt(s.heteroscedasticity, 3) + ", z " + fmt(s.heteroscedasticity_z, 3) + ")"});
  if (std::isfinite(s.input_z) && s.input_z > 4)
    f.push_back({s.input_z, "innovations correlated with the input (corr " + fmt(s.input_correlation, 3) + " at lag " +
                                std::to_string(s.input_lag) + ", z " + fmt(s.input_z, 3) + ")"});
  if (std::isfinite(s.line_z) && s.line_z > 4)
    f.push_back({s.line_z, "a spectral line in the innovations at " + fmt(s.line_frequency, 4) + " rad/time (z " + fmt(s.line_z, 3) + ")"});
  if (std::abs(std::log(s.variance)) * std::sqrt(n / 2.0) > 4)
    f.push_back({std::abs(std::log(s.variance)) * std::sqrt(n / 2.0), "innovation variance " + fmt(s.variance, 3) + " times the filter's prediction"});
  std::sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [zv, text] : f) s.summary += (s.summary.empty() ? "" : "; ") + text;
  s.features = static_cast<int>(f.size());
  if (s.summary.empty()) s.summary = "the held-out innovations show no feature beyond 4 standard errors";
  return s;
}

}  // namespace vehs::diagnose
