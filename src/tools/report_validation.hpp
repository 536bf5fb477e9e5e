#pragma once
// What a system-identification reviewer checks on a driven model, for the diagnosis report:
// measured vs simulated (the model's noise-free free run under the recorded input) with the fit
// percentage of MATLAB's `compare`, fit = 100 (1 − ‖y − ŷ‖ / ‖y − mean(y)‖), and the
// cross-correlation of the model's one-step residuals with the input (MATLAB's `resid`) with its
// 99 % band under independence (Bartlett: var r(τ) = Σ_j ρ_e(j) ρ_u(j) / N).
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs::tools {

struct DrivenValidation {
  bool available = false;
  std::string note;                           ///< why not available, or what was left out
  std::vector<double> t, measured, simulated; ///< the first record's scored segment
  double fit_percent = 0.0;                   ///< pooled over the records used, after the transient
  std::vector<double> record_fit;             ///< per record
  std::vector<double> lag, xcorr, band;       ///< lag (time units; > 0: input leads), r(τ), 99 % half-width
  double worst_ratio = 0.0;                   ///< largest |r(τ)| / band over the lags
  double worst_lag = 0.0;
};

/// Free runs and residual–input correlation on at most `max_records` records of at most
/// `max_samples` samples each. Not available (with the reason) when the data have no input.
DrivenValidation driven_validation(const Model& model, const Dataset& data, std::size_t max_records = 8,
                                   std::size_t max_samples = 20000);

}  // namespace vehs::tools
