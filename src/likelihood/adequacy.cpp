#include "vehs/likelihood/adequacy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"

namespace vehs::likelihood {

double hidden_state_rate_dt(const Model& fit, double dt) {
  double r = 0.0;
  for (const Effect& e : fit.effects) {
    if (e.id == EffectId::ElectromechanicalCoupling && e.params.count("lambda"))
      r = std::max(r, std::abs(e.param("lambda")) * dt);
    if (e.id == EffectId::ColoredNoise && e.params.count("tau") && e.param("tau") > 0.0)
      r = std::max(r, dt / e.param("tau"));
  }
  return r;
}

namespace {

/// Why the moment fit cannot stand although ω̂Δt is small ("" when nothing speaks against it):
/// the sampling diagnosis found white sensor noise at the recorded rate (noise that shows white
/// only at a longer stride, such as quantisation at a fast rate, is not the likelihood's white
/// measurement noise: the noisy estimator's fit at that stride stands), or the model has a
/// hidden state whose moment reconstruction is biased at first order in its rate × Δt.
template <class Format>
std::string moment_fit_doubt(const Model& fit, const Dataset& data, double best_relative_se, const Format& g) {
  if (fit.fit) {
    const SamplingDiagnosis& s = fit.fit->sampling;
    if (s.verdict == SamplingVerdict::Noisy && s.stride == 1)
      return ": white sensor noise (" +
             (s.noise_share < 0.95 ? "about " + g(100.0 * s.noise_share) + " % of the ULI acceleration's variance"
                                   : std::string("the ULI acceleration looks white at the recorded step, share not resolved")) +
             "): the noisy estimator's expansion leaves biased "
             "estimates and too small SEs; the likelihood models the noise";
  }
  const double dt = data.records.empty() ? 0.0 : data.records.front().dt;
  const double rate_dt = hidden_state_rate_dt(fit, dt);
  if (2.0 * rate_dt > best_relative_se)
    return ": a hidden state with rate*dt = " + g(rate_dt) + ": the moment fit's first-order bias, about 2 rate*dt = " +
           g(2.0 * rate_dt) + " relative, exceeds the best relative SE " + g(best_relative_se);
  return "";
}

}  // namespace

double stiffness_omega_dt(const Model& fit, const Dataset& data) {
  if (data.records.empty() || data.x.empty()) return 0.0;
  const std::size_t step = std::max<std::size_t>(1, data.x.size() / 100000);
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < data.x.size(); i += step, ++n) {
    double k = 0.0;  // −∂f/∂x at (x, y = 0, u = 0)
    for (const auto& tc : fit.drift)
      if (!tc.term.depends_on_u()) k -= tc.coef * tc.term.d_dx(data.x[i], 0.0);
    if (std::isfinite(k)) sum += std::max(k, 0.0);
  }
  return std::sqrt(sum / double(n)) * data.records.front().dt;
}

double input_omega_dt(const Dataset& data) {
  if (!data.has_u()) return 0.0;
  // two passes: a drive far from zero (a force offset, raw ADC counts) keeps its variance
  double sum = 0.0;
  std::size_t n = 0;
  for (const Record& r : data.records)
    for (std::size_t k = 0; k < r.size; ++k) sum += data.u_of(r)[k], ++n;
  if (n < 2) return 0.0;
  const double mean = sum / double(n);
  double var = 0.0, diff2 = 0.0;
  std::size_t nd = 0;
  for (const Record& r : data.records) {
    const double* u = data.u_of(r);
    for (std::size_t k = 0; k < r.size; ++k) {
      var += (u[k] - mean) * (u[k] - mean);
      if (k > 0) diff2 += (u[k] - u[k - 1]) * (u[k] - u[k - 1]), ++nd;
    }
  }
  var /= double(n);
  return var > 0.0 && nd > 0 ? std::sqrt(diff2 / double(nd) / var) : 0.0;
}

SamplingAdequacy assess_sampling(const Model& fit, const Dataset& data) {
  SamplingAdequacy a;
  a.increments_omega_dt = dominant_omega_dt(data);
  a.stiffness_omega_dt = stiffness_omega_dt(fit, data);
  a.omega_dt = std::isfinite(a.increments_omega_dt) ? std::max(a.increments_omega_dt, a.stiffness_omega_dt)
                                                    : a.increments_omega_dt;
  a.bias = a.omega_dt * a.omega_dt / 12.0;
  a.best_relative_se = std::numeric_limits<double>::infinity();
  for (const auto& tc : fit.drift) {
    const auto it = fit.drift_stderr.find(tc.term.name());
    if (tc.coef != 0.0 && it != fit.drift_stderr.end() && it->second > 0.0)
      a.best_relative_se = std::min(a.best_relative_se, it->second / std::abs(tc.coef));
  }
  a.recorded_input = fit.uses_drive();
  if (a.recorded_input) a.input_omega_dt = input_omega_dt(data);
  const auto g = [](double v) { return vehs::detail::format_number(v, 3); };
  if (!std::isfinite(a.omega_dt)) {
    a.reason = "the data's dominant frequency is undefined (constant or too short records)";
    return a;
  }
  const std::string w =
      "omega*dt = " + g(a.omega_dt) +
      (a.stiffness_omega_dt > a.increments_omega_dt
           ? " (the fitted drift's stiffness over the data; the increments of x give " + g(a.increments_omega_dt) + ")"
           : "");
  if (a.omega_dt >= 0.2) {
    a.vouched = false;
    a.reason = w + ": fewer than 31 samples per period, where the expansions' bias is not bounded by (omega*dt)^2/12 = " +
               g(a.bias) + " (clean Duffing records at omega*dt 0.29 gave a spurious x^2*y at z -12 to -14)";
  } else if (a.omega_dt >= 0.1 && a.bias > a.best_relative_se) {
    a.vouched = false;
    a.reason = w + ": the expansions' relative bias (omega*dt)^2/12 = " + g(a.bias) +
               " exceeds the best relative standard error " + g(a.best_relative_se);
  } else if (a.recorded_input && a.omega_dt >= 0.1) {
    a.vouched = false;
    a.reason = w + " with a recorded input: holding u over an interval delays it by dt/2, a phase error of " +
               g(a.omega_dt / 2) + " rad";
  } else if (a.recorded_input && a.input_omega_dt / 2 > a.best_relative_se) {
    a.vouched = false;
    a.reason = w + " with an input that changes fast (its own omega*dt = rms(du)/sd(u) = " + g(a.input_omega_dt) +
               "): holding u over an interval delays it by dt/2, a phase error of " + g(a.input_omega_dt / 2) +
               " rad, above the best relative standard error " + g(a.best_relative_se);
  } else if (!std::isfinite(a.best_relative_se)) {
    a.vouched = false;
    a.reason = w + ": the moment fit resolved no drift coefficient (each is zero or has no standard error), so no "
                   "standard error bounds the expansions' bias; the likelihood refits from every start";
  } else if (const std::string why = moment_fit_doubt(fit, data, a.best_relative_se, g); !why.empty()) {
    a.vouched = false;
    a.reason = w + why;
  } else {
    a.reason = w + ": the expansions in dt hold (bias " + g(a.bias) + " vs best relative SE " +
               g(a.best_relative_se) + ")";
  }
  return a;
}

}  // namespace vehs::likelihood
