// Which moment estimator identify's `auto` uses (estimator_choice.hpp): the sampling rule's
// reading of the pilot, values on a grid, and the fit's residuals over all rows.
#include "estimator_choice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/core/quantisation.hpp"

namespace vehs::identify::detail {

namespace {
std::string fmt(double v) { return vehs::detail::format_number(v, 4); }

/// A rounding share from which values on a grid are read as a sensor's: an ADC adds its own white
/// noise to the rounding's (12-bit counts with 1 LSB of noise: rounding 8 % of â's variance, the
/// lag-1 autocorrelation 0.02), so the grid is the evidence, not the share it explains; below
/// 1 % the grid is a printout's with many decimals (an explicit scheme's output keeps its verdict).
constexpr double kRoundingMatters = 0.01;

/// An ADC's own white noise beside its rounding, as a multiple of the rounding's variance q²/12:
/// 1 LSB of noise (12×) is common. The ULI diffusion corrects the rounding only; the rest biases
/// a22 up by its share of â's variance (16-bit counts at 5 kHz with 0.3 LSB of ADC noise, rounding
/// 0.9 % of â's variance: 2D +1.2 %, z +3.8 to +6.4 on 4·10⁵ samples, 3 of 4 seeds, exit 0).
constexpr double kAdcNoiseOverRounding = 12.0;

/// Whether that unknown ADC noise could move a22 by more than its standard error, ≈ √(2/n)
/// relative on n rows: then the noisy estimator's noise-free diffusion target is used.
bool adc_noise_matters(double rounding, double rows) {
  return rounding > 0.0 && kAdcNoiseOverRounding * rounding > std::sqrt(2.0 / std::max(rows, 1.0));
}

}  // namespace

/// The share of the ULI acceleration's variance that a grid's rounding (white, q²/12) makes at
/// the pilot's stride: 6 (q²/12)/h⁴ over the residuals' mean square (0 off a grid).
double rounding_share(const Pilot& diag, const Quantisation& quant, double dt) {
  const double h = diag.k * dt;
  if (!quant.quantised() || !(diag.V > 0.0) || !(h > 0.0)) return 0.0;
  return std::min(1.0, 6.0 * quant.noise_variance() / (h * h * h * h * diag.V));
}

std::string noise_share_text(double share) {
  // 100 % is pure white noise, no motion at all: a saturated reading says only that the lags
  // look white at this stride (fast motion sampled coarsely reads the same), not how much noise
  if (!(share < kSaturatedNoiseShare))
    return "the ULI acceleration looks white at the recorded step (sensor noise or motion too fast for the "
           "sampling; the share of sensor noise is not resolved there)";
  return "white sensor noise makes up about " + fmt(100 * share) + " % of the variance of the ULI acceleration";
}

std::string grid_step_text(double q) { return std::string(kGridStepLead) + fmt(q); }

EstimatorDecision choose_estimator(const Pilot& diag, Estimator requested, double omega_dt, double rounding,
                                   double grid_step, double rows) {
  EstimatorDecision d;
  d.estimator = requested;
  const SamplingRule rule = sampling_rule(diag.rho_k, diag.rho_2k, diag.rho_3k, diag.rows);
  d.verdict = rule.verdict;
  d.unexplained = sampling_unexplained(rule.verdict, diag.rho_k, diag.rho_3k, omega_dt);
  if (requested != Estimator::Auto) return d;
  const std::string at = diag.k > 1 ? " at stride " + std::to_string(diag.k) : "";
  if (rule.noisy) {
    d.estimator = Estimator::Noisy;
    d.reason = noise_share_text(rule.noise_share) + " (lag-2k autocorrelation " + fmt(diag.rho_2k) +
               " above lag-3k " + fmt(diag.rho_3k) + at + ")";
  } else if (rule.continuous && adc_noise_matters(rounding, rows)) {
    d.estimator = Estimator::Noisy;
    d.reason = "ULI residuals have lag-" + std::string(diag.k > 1 ? "k" : "1") + " autocorrelation " + fmt(diag.rho_k) + at +
               " (about +1/4: a sensor sampling a continuous-time process); the values lie on " +
               grid_step_text(grid_step) + " whose rounding makes " + fmt(100 * rounding) +
               " % of the ULI acceleration's variance: an ADC's own noise beside it (up to " + fmt(kAdcNoiseOverRounding) +
               "x the rounding's variance) would bias the ULI diffusion beyond its standard error on " + fmt(rows) +
               " rows, so noisy (its diffusion target is free of white noise) used";
  } else if (rule.continuous) {
    d.estimator = Estimator::Uli;
    d.reason = "ULI residuals have lag-" + std::string(diag.k > 1 ? "k" : "1") + " autocorrelation " + fmt(diag.rho_k) + at +
               " (about +1/4: a sensor sampling a continuous-time process)";
  } else if (rounding >= kRoundingMatters) {
    // values on a grid come from a sensor, not from an explicit scheme: its rounding is white
    // noise on a continuous process, and the mixture's lag-1 autocorrelation lands between the
    // two signatures (+1/4, −2/3), near 0 (an outside tester's Duffing in 10-bit counts at 1 kHz
    // and 12-bit counts with 1 LSB of ADC noise: forward chosen on 10 of 18 files, 2D at z −7.6
    // to −44.6, damping at −5 to −7 and a spurious x²·y)
    d.estimator = Estimator::Noisy;
    d.reason = "ULI residuals have lag-" + std::string(diag.k > 1 ? "k" : "1") + " autocorrelation " + fmt(diag.rho_k) +
               at + ", but the values lie on " + grid_step_text(grid_step) + " whose rounding makes " +
               fmt(100 * rounding) +
               " % of the ULI acceleration's variance (a sensor's rounding, white noise on a continuous process, "
               "not an explicit scheme): noisy used";
  } else if (d.unexplained) {
    d.estimator = Estimator::Forward;
    d.reason = "ULI residuals have lag-1 autocorrelation " + fmt(diag.rho_k) +
               ", neither about 0 (an explicit scheme at the recorded step) nor about +1/4 (a sensor on a "
               "continuous process): quantised values, dropouts, stuck or clipped stretches? forward used";
  } else {
    d.estimator = Estimator::Forward;
    d.reason = "ULI residuals have lag-1 autocorrelation " + fmt(diag.rho_k) +
               " (about 0: data from an explicit one-step scheme at the recorded step)";
  }
  return d;
}

/// White sensor noise of share η in â's variance lowers the ULI residuals' lag-k autocorrelation
/// from 1/4 to 1/4 − (11/12)η, and the ULI diffusion, which takes the noise for diffusion, is
/// then about η too high. The pilot's lag-2k reading (sampling_rule) resolves η only to ≈ 8.5/√rows
/// (2.7 % on its 2.5·10⁵ rows) and its lag-k reading moves with ω·h, while over all the rows of
/// the final fit lag k sits at 1/4 within ≈ 1/√rows on clean continuous-time records (0.2485–0.2503
/// on 4·10⁵ rows of a Duffing at ω·h 0.013–0.19). Float records of that Duffing with white noise
/// of 0.004 % of sd(x) at 5 kHz read 0.230–0.233 there (η ≈ 2 %), and the ULI fit wrote 2D at
/// z +7.5 to +10.9 with exit 0. The share read from lag k; NaN when the fit is not auto's ULI.
double residual_noise_share(const Result& r, const Options& options) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (options.estimator != Estimator::Auto || options.stride != 0 || !r.model.fit || r.model.fit->estimator != Estimator::Uli)
    return nan;
  const double rho = r.report.residuals.autocorrelation_at(r.model.fit->stride);
  return std::isfinite(rho) ? (12.0 / 11.0) * (0.25 - rho) : nan;
}

namespace {
/// The standard error of the lag-k autocorrelation of the ULI residuals, an MA(1) with ρ 1/4:
/// Bartlett's √((1 − 3ρ² + 4ρ⁴)/rows), times √κ for a state-dependent variance (κ =
/// E[r⁴]/(3E[r²]²), ≥ 1 taken).
double lag_k_se(const ResidualReport& rr) {
  return std::sqrt((1.0 - 3.0 / 16.0 + 4.0 / 256.0) * std::max(rr.kurtosis_factor, 1.0) / std::max(rr.rows, 1.0));
}
}  // namespace

/// Noise is read when lag k is 4 of its standard errors below 1/4 (a clean fit is sent to noisy,
/// unbiased but with a22's SE about 1.35× the ULI one, with probability 3·10⁻⁵). The bias left
/// below that bar: up to ≈ 1.6 SE of a22 per SE of lag k (outside testers' 16-bit counts at 1 kHz
/// with 0.3 LSB of ADC noise: lag k 2.4σ low, 2D z +3.8).
bool residual_noise_matters(double eta, const ResidualReport& rr) {
  return (11.0 / 12.0) * eta > 4.0 * lag_k_se(rr);
}

std::string residual_noise_reason(const ResidualReport& rr, double eta) {
  return "; but the ULI fit's residuals over all " + std::to_string(static_cast<long long>(rr.rows)) +
         " rows have lag-k autocorrelation " + fmt(0.25 - (11.0 / 12.0) * eta) + ", below 1/4 by " +
         fmt((11.0 / 12.0) * eta / lag_k_se(rr)) + " SE: white sensor noise of about " + fmt(100.0 * eta) +
         " % of the ULI acceleration's variance, which the ULI diffusion would take for diffusion; noisy (a "
         "diffusion target free of white noise) used";
}

}  // namespace vehs::identify::detail
