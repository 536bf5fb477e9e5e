#pragma once
// Internal: which moment estimator identify's `auto` uses — from the pilot's sampling diagnosis
// (the lags of the ULI residuals, a grid's rounding) before the fit, and from the fit's own
// residuals over all rows after a ULI fit (white sensor noise too small for the pilot to see).
#include <string>
#include <string_view>

#include "pilot.hpp"
#include "vehs/core/quantisation.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::identify::detail {

/// The estimator: the requested one, or (auto) what the pilot's sampling diagnosis says.
struct EstimatorDecision {
  Estimator estimator = Estimator::Forward;
  std::string reason = "requested";
  SamplingVerdict verdict = SamplingVerdict::Unknown;
  bool unexplained = false;  ///< sampling_unexplained (core/fit_info.hpp) at the pilot's stride
};


/// The share of the ULI acceleration's variance that a grid's rounding (white, q²/12) makes at
/// the pilot's stride: 6 (q²/12)/h⁴ over the residuals' mean square (0 off a grid).
double rounding_share(const Pilot& diag, const Quantisation& quant, double dt);

/// A noise share read at or above this (η = 6 (ρ_2k − ρ_3k) clamped to 1) is saturated: the
/// lags look white, which says nothing of how much of it is sensor noise.
inline constexpr double kSaturatedNoiseShare = 0.95;

/// The noisy verdict's wording: the share "about 12 %" when resolved, else that the lags look
/// white without a share.
std::string noise_share_text(double share);

/// "a grid of step q": the phrase the estimator's reason names a quantisation step by (identify
/// rewrites q in the data's units after a fit in internal units).
inline constexpr std::string_view kGridStepLead = "a grid of step ";
std::string grid_step_text(double q);

/// The estimator for the pilot's diagnosis (`requested` unless it is auto): noisy, uli or forward,
/// with the figures that decided in the reason (estimator_choice.cpp gives the rules).
EstimatorDecision choose_estimator(const Pilot& diag, Estimator requested, double omega_dt, double rounding,
                                   double grid_step, double rows);

/// The white-noise share η read from lag k of an auto ULI fit's residuals over all rows
/// (1/4 − (11/12)η); NaN when `r` is not such a fit.
double residual_noise_share(const Result& r, const Options& options);

/// Whether that share is read as noise (lag k 4 of its standard errors below 1/4): then the data
/// are refitted with noisy.
bool residual_noise_matters(double eta, const ResidualReport& rr);

/// The clause appended to the estimator's reason when that refit is made.
std::string residual_noise_reason(const ResidualReport& rr, double eta);

}  // namespace vehs::identify::detail
