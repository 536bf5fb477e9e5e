#pragma once
// How identify fitted a model, typed: the estimator and why it was chosen, the residual
// diagnostics, the sparse-regression paths with their CV and BIC figures, conditioning and
// timing, the effects' physical parameters, and the details of the dynamic-effect fits. The
// estimator, its stride and the sampling diagnosis travel with the model itself (Model::fit).
// identify-vehs writes all of it into the model file (src/tools/identify_file.cpp).
#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/user_effect.hpp"
#include "vehs/identify/regression.hpp"

namespace vehs::identify {

/// Which estimator ran and why (Model::fit holds the estimator used and its stride).
struct EstimatorChoice {
  Estimator requested = Estimator::Auto;
  std::string reason;                      ///< "requested", or the sampling figures that decided
  bool discretization_correction = false;  ///< (h²/12)·x⁗ removed from the acceleration target
  SsrRule ssr_rule = SsrRule::TRatio;
  /// The sampling rule explains the data at no stride tried (core/fit_info.hpp,
  /// sampling_unexplained): quantised values, dropouts, stuck or clipped stretches?
  bool sampling_unexplained = false;
};

/// Diagnostics of the final drift residuals.
struct ResidualReport {
  double rows = 0.0;
  double rms = 0.0;
  /// E[r⁴]/(3 E[r²]²): 1 for Gaussian residuals of one variance, more for a state-dependent one
  /// (the variance of a sample autocorrelation grows by this factor).
  double kurtosis_factor = 1.0;
  std::vector<std::pair<int, double>> autocorrelation;  ///< (lag in samples, ρ)
  /// ρ at lag k expected for the estimator: 1/4 for uli, 0 for forward and paper, NaN for noisy.
  double expected_lag_k = std::numeric_limits<double>::quiet_NaN();
  double long_run_factor_drift = 1.0;      ///< φ of the drift BIC
  double long_run_factor_diffusion = 1.0;  ///< φ of the diffusion BIC

  /// ρ at `lag` (NaN when not measured).
  double autocorrelation_at(int lag) const {
    for (const auto& [l, rho] : autocorrelation)
      if (l == lag) return rho;
    return std::numeric_limits<double>::quiet_NaN();
  }
};

/// A sparse-regression path and the dictionary its supports index.
struct SelectionReport {
  std::vector<Term> dictionary;
  SelectionResult selection;
};

struct FitSummary {
  std::size_t rows = 0;  ///< regression rows used
  std::size_t rows_left_out = 0;  ///< rows left out where the lens's expansion in h does not hold (a state-dependent diffusion)
  double drift_condition_full = 0.0;  ///< of the full drift library
  double drift_condition_selected = std::numeric_limits<double>::quiet_NaN();
  double diffusion_condition_full = 0.0;
  double stderr_batches = 0.0;  ///< batches of the batch-means score covariance
  int stderr_batch_rows = 0;    ///< rows per batch
  double seconds = 0.0;
  std::vector<std::pair<std::string, double>> timings;  ///< seconds per stage
};

// ---- dynamic effects fitted by profile least squares (impact_stop, harmonic_forcing,
// electromechanical_coupling)

struct SpectralLine {
  double frequency = 0.0;           ///< cycles per time unit
  double peak_to_background = 0.0;
};

/// How the nonlinear parameters of one dynamic effect were started (first round).
struct ComponentSearch {
  EffectId effect{};
  std::optional<double> grid_quantile;               ///< impact_stop: best quantile of |x|
  std::optional<std::array<double, 3>> lambda_grid;  ///< electromechanical_coupling: lo, hi, points
  std::size_t spectrum_segment = 0;                  ///< harmonic_forcing: Welch segment (0: none)
  std::vector<SpectralLine> spectral_lines;          ///< harmonic_forcing: the largest lines
  std::optional<double> scan_step;                   ///< harmonic_forcing: frequency scan step
};

struct ProfileRound {
  Estimator estimator = Estimator::Uli;
  int stride = 1;
  std::vector<Term> drift_terms;  ///< the baseline support of the round
  std::vector<Effect> effects;    ///< fitted at the end of the round
  double profile_contrast = 0.0;
};

struct ProfileFitReport {
  std::vector<ComponentSearch> search;  ///< the last round's search (first round: grids)
  int newton_iterations = -1;           ///< joint Newton steps of the last round (−1: none)
  std::vector<ProfileRound> rounds;
  std::vector<Effect> effects;          ///< the final fit, with standard errors
  double profile_contrast = 0.0;
  double rows = 0.0;
  std::optional<std::array<double, 2>> samples_beyond_gap;  ///< impact_stop: positive, negative
};

// ---- colored_noise (OU excitation) from the residual autocovariance and GLS

struct ColoredRound {
  double tau = 0.0, intensity = 0.0;
  int lag_lo = 0, lag_hi = 0;  ///< lags (samples) of the exponential fit
};

struct ColoredFitReport {
  std::vector<ColoredRound> rounds;
  double lag_lo_time = 0.0, lag_hi_time = 0.0;  ///< the fitted lag range in time units
  double eta_variance_in_residual = 0.0;         ///< σ²·Q, the OU part of E[r²]
  double residual_variance = 0.0;
};

struct Report {
  EstimatorChoice estimator;
  ResidualReport residuals;
  SelectionReport drift_selection, diffusion_selection;
  Sparsity sparsity = Sparsity::Ssr;
  Criterion criterion = Criterion::Bic;
  int folds = 0;
  FitSummary fit;
  /// Physical parameters of the requested effects with standard errors: term-like ones from
  /// their coefficients (e.g. mu = −coef of sign(y)), then the dynamic ones.
  std::vector<Effect> effect_params;
  /// The user effects' parameters (Options::user_effects) with standard errors.
  std::vector<UserEffectFit> user_effect_params;
  std::optional<ProfileFitReport> profile;  ///< set when dynamic forces were fitted
  std::optional<ColoredFitReport> colored;  ///< set when colored_noise was fitted
};

}  // namespace vehs::identify
