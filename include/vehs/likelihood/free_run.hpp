#pragma once
// Free-run simulation of a model (no process or measurement noise) driven by a recorded input,
// and the validation figures system identification reports: the simulated output at the
// record's samples, measured vs simulated, and the RMSE after a transient. The continuous model
// is integrated (RK4 substeps) with the input held or interpolated between samples, as in the
// likelihood. Free of file formats: the tools write the series and figures.
#include <cstddef>
#include <optional>
#include <vector>

#include "vehs/core/model.hpp"
#include "vehs/likelihood/filter.hpp"

namespace vehs::likelihood {

struct InitialState {
  double x = 0.0, y = 0.0;
  double v = 0.0;    ///< electromechanical state
  double eta = 0.0;  ///< coloured excitation (its mean, 0, for a noise-free run)
};

struct FreeRunOptions {
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  int substeps = 8;                   ///< RK4 substeps per sampling interval
  double t0 = 0.0;                    ///< time of the first sample (harmonic forcing)
  std::optional<double> phase;        ///< harmonic_forcing phase of this record (else the model's)
  double divergence_bound = 1e6;      ///< |x| or |y| beyond this (in units of the data) is an error
};

/// x at t0 + k·dt, k = 0 … samples − 1, from `initial`. `u` (the input at the same samples) is
/// required when the model has a drive term and must have at least `samples` values. Throws
/// vehs::Error (one line) for a short input, a non-positive dt, or a run that diverges.
std::vector<double> free_run(const Model& model, const InitialState& initial,
                             const std::vector<double>& u, double dt, std::size_t samples,
                             const FreeRunOptions& options = {});

struct Validation {
  std::vector<double> measured, simulated;  ///< the segment, sample by sample
  std::size_t skip = 0;                     ///< leading samples left out of the scores
  double rmse = 0.0;                        ///< over samples [skip, n)
  double measured_rms = 0.0;                ///< rms of the measured output over the same samples
  InitialState initial;                     ///< the state the run started from
};

/// Free-run validation on a measured segment x[0 … n) with input u[0 … n): the run starts from
/// the measured initial state (x[0] and the second-order one-sided difference
/// (−3x₀ + 4x₁ − x₂)/2Δt, unless `initial` is given) and is scored after `skip` samples.
Validation validate_free_run(const Model& model, const std::vector<double>& x,
                             const std::vector<double>& u, double dt, std::size_t skip,
                             const FreeRunOptions& options = {},
                             const std::optional<InitialState>& initial = std::nullopt);

}  // namespace vehs::likelihood
