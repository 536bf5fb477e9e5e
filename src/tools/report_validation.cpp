#include "tools/report_validation.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/free_run.hpp"

namespace vehs::tools {

namespace {

constexpr int kMaxLag = 40;          ///< lags shown, in samples, each side
constexpr int kBartlettLags = 200;   ///< autocorrelation lags summed for the band

/// Normalised autocorrelation of a centred series up to `lags`.
std::vector<double> acf(const std::vector<double>& a, int lags) {
  std::vector<double> r(static_cast<std::size_t>(lags) + 1, 0.0);
  const std::size_t n = a.size();
  for (int j = 0; j <= lags && static_cast<std::size_t>(j) < n; ++j) {
    double s = 0.0;
    for (std::size_t i = static_cast<std::size_t>(j); i < n; ++i) s += a[i] * a[i - static_cast<std::size_t>(j)];
    r[static_cast<std::size_t>(j)] = s;
  }
  const double r0 = r[0] > 0 ? r[0] : 1.0;
  for (double& v : r) v /= r0;
  return r;
}

void centre(std::vector<double>& a) {
  double m = 0.0;
  for (double v : a) m += v;
  m /= static_cast<double>(std::max<std::size_t>(a.size(), 1));
  for (double& v : a) v -= m;
}

/// One-step residuals â − b2(x, v̂, u) at the model's stride (central differences) and the input
/// at the same rows, pooled over the records used (each centred).
void residual_input_correlation(const Model& model, const Dataset& data, std::size_t records, std::size_t max_samples,
                                DrivenValidation& out) {
  const std::size_t k = model.fit && model.fit->stride > 0 ? static_cast<std::size_t>(model.fit->stride) : 1;
  std::vector<double> sxy(2 * kMaxLag + 1, 0.0), rho(kBartlettLags + 1, 0.0);
  double see = 0.0, suu = 0.0, n_total = 0.0;
  for (std::size_t ri = 0; ri < records; ++ri) {
    const Record& r = data.records[ri];
    if (r.size < 4 * k + 2 * kMaxLag + 10) continue;
    const double* x = data.x_of(r);
    const double* u = data.u_of(r);
    const double h = static_cast<double>(k) * r.dt;
    const std::size_t n = std::min(r.size, max_samples);
    std::vector<double> e, uu;
    for (std::size_t i = k; i + k < n; ++i) {
      const double v = (x[i + k] - x[i - k]) / (2 * h), a = (x[i + k] - 2 * x[i] + x[i - k]) / (h * h);
      e.push_back(a - model.b2(x[i], v, u[i]));
      uu.push_back(u[i]);
    }
    centre(e);
    centre(uu);
    const auto re = acf(e, kBartlettLags), ru = acf(uu, kBartlettLags);
    double ee = 0.0, q = 0.0;
    for (std::size_t i = 0; i < e.size(); ++i) ee += e[i] * e[i], q += uu[i] * uu[i];
    const double m = static_cast<double>(e.size());
    for (int j = 0; j <= kBartlettLags; ++j) rho[static_cast<std::size_t>(j)] += m * re[static_cast<std::size_t>(j)] * ru[static_cast<std::size_t>(j)];
    for (int tau = -kMaxLag; tau <= kMaxLag; ++tau) {  // Σ e[i] u[i − τ]
      double s = 0.0;
      for (std::size_t i = 0; i < e.size(); ++i) {
        const long j = static_cast<long>(i) - tau;
        if (j >= 0 && j < static_cast<long>(uu.size())) s += e[i] * uu[static_cast<std::size_t>(j)];
      }
      sxy[static_cast<std::size_t>(tau + kMaxLag)] += s;
    }
    see += ee, suu += q, n_total += m;
  }
  if (n_total == 0 || see <= 0 || suu <= 0) return;
  double var = rho[0] / n_total;  // Σ_j over j = −J … J of ρ_e ρ_u, divided by N
  for (int j = 1; j <= kBartlettLags; ++j) var += 2 * rho[static_cast<std::size_t>(j)] / n_total;
  const double band = 2.5758 * std::sqrt(std::max(var, 0.0) / n_total);
  const double dt = data.records.front().dt;
  for (int tau = -kMaxLag; tau <= kMaxLag; ++tau) {
    const double r = sxy[static_cast<std::size_t>(tau + kMaxLag)] / std::sqrt(see * suu);
    out.lag.push_back(tau * dt), out.xcorr.push_back(r), out.band.push_back(band);
    if (band > 0 && std::abs(r) / band > out.worst_ratio) out.worst_ratio = std::abs(r) / band, out.worst_lag = tau * dt;
  }
}

}  // namespace

DrivenValidation driven_validation(const Model& model, const Dataset& data, std::size_t max_records,
                                   std::size_t max_samples) {
  DrivenValidation out;
  if (data.u.empty() || data.records.empty()) {
    out.note = "the data have no input column: no free run under the recorded input";
    return out;
  }
  const std::size_t records = std::min(max_records, data.records.size());
  double sse = 0.0, sst = 0.0;
  for (std::size_t ri = 0; ri < records; ++ri) {
    const Record& r = data.records[ri];
    const std::size_t n = std::min(r.size, max_samples);
    if (n < 20) continue;
    const std::vector<double> x(data.x_of(r), data.x_of(r) + n), u(data.u_of(r), data.u_of(r) + n);
    likelihood::FreeRunOptions fr;
    if (model.fit) fr.input = model.fit->input;
    fr.t0 = r.t0;
    const std::size_t skip = std::min<std::size_t>(n / 10, 500);
    likelihood::Validation v;
    try {
      v = likelihood::validate_free_run(model, x, u, r.dt, skip, fr);
    } catch (const Error& e) {
      out.note = std::string("free run of record ") + std::to_string(ri + 1) + ": " + e.what();
      return out;
    }
    double mean = 0.0;
    for (std::size_t i = skip; i < n; ++i) mean += x[i];
    mean /= static_cast<double>(n - skip);
    double e2 = 0.0, d2 = 0.0;
    for (std::size_t i = skip; i < n; ++i)
      e2 += (x[i] - v.simulated[i]) * (x[i] - v.simulated[i]), d2 += (x[i] - mean) * (x[i] - mean);
    out.record_fit.push_back(d2 > 0 ? 100 * (1 - std::sqrt(e2 / d2)) : 0.0);
    sse += e2, sst += d2;
    if (ri == 0) {
      const std::size_t shown = std::min(n, skip + 2000);
      for (std::size_t i = skip; i < shown; ++i)
        out.t.push_back(r.t0 + static_cast<double>(i) * r.dt), out.measured.push_back(x[i]), out.simulated.push_back(v.simulated[i]);
    }
  }
  if (out.record_fit.empty()) {
    out.note = "no record is long enough for a free run";
    return out;
  }
  out.fit_percent = sst > 0 ? 100 * (1 - std::sqrt(sse / sst)) : 0.0;
  residual_input_correlation(model, data, records, max_samples, out);
  out.available = true;
  if (records < data.records.size())
    out.note = "the first " + std::to_string(records) + " of " + std::to_string(data.records.size()) + " records";
  return out;
}

}  // namespace vehs::tools
