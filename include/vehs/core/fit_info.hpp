#pragma once
// What a model says about the fit that produced it: the estimator, its stride and how the data it
// was fitted to were sampled. identify sets it (Model::fit) and the model file carries it
// ("estimator" and "sampling"); diagnose reads it to look at data through the same lens and to
// refuse data sampled at another interval. A model built in C++ may set it or leave it empty.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vehs/core/enum_names.hpp"

namespace vehs {

/// The identification estimators (vehs/identify/identify.hpp describes each).
enum class Estimator { Auto, Paper, Forward, Uli, Noisy };
inline constexpr EnumNames<Estimator, 5> kEstimatorNames{{{Estimator::Auto, "auto"},
                                                         {Estimator::Paper, "paper"},
                                                         {Estimator::Forward, "forward"},
                                                         {Estimator::Uli, "uli"},
                                                         {Estimator::Noisy, "noisy"}}};

/// Central (ULI) kinematics on a stride, as opposed to forward differences at the recorded step.
inline bool uses_central_kinematics(Estimator e) { return e == Estimator::Uli || e == Estimator::Noisy; }

/// How the data were sampled, as the lag autocorrelations of ULI residuals show it
/// (identify::sampling_rule).
enum class SamplingVerdict { Unknown, SchemeConsistent, ContinuousTime, Noisy };
inline constexpr EnumNames<SamplingVerdict, 4> kSamplingVerdictNames{
    {{SamplingVerdict::Unknown, "unknown"},
     {SamplingVerdict::SchemeConsistent, "scheme-consistent"},
     {SamplingVerdict::ContinuousTime, "continuous-time"},
     {SamplingVerdict::Noisy, "noisy"}}};

/// Lag-k autocorrelation of ULI residuals far below both readings of the sampling rule: about 0
/// for a scheme at the recorded step, about +1/4 for a sensor on a continuous process. White
/// sensor noise pulls it towards −2/3 but is then seen at lag 2k too (the Noisy verdict); what
/// pulls it down WITHOUT that is something else in the data: quantised values (integer ADC
/// counts at a fast rate: −0.50), dropouts written as 0 (−0.18), stuck or clipped stretches.
/// The margin 0.15 is 5 standard errors of the estimate on a pilot of 1000 rows. Only read
/// where the readings hold, ω̂Δt < 0.2 (vehs/core/dominant_frequency.hpp): coarsely sampled
/// dynamics push lag k below 0 too (Silverbox, ω̂Δt ≈ 0.7).
inline bool sampling_unexplained(SamplingVerdict verdict, double rho_k, double rho_3k, double omega_dt) {
  return omega_dt < 0.2 && verdict == SamplingVerdict::SchemeConsistent && rho_k - rho_3k < -0.15;
}

/// The sampling diagnosis of identify's pilot fit (the model file's "sampling"). Figures that
/// were not measured (a model file that does not state them) are NaN; dt is 0 when unknown.
struct SamplingDiagnosis {
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double dt = 0.0;              ///< sampling interval of the data
  int stride = 0;               ///< stride k at which the figures below were measured (0: unknown)
  double rho_1 = kUnknown;      ///< lag-1 autocorrelation of pilot ULI residuals
  double rho_k = kUnknown;      ///< lag-k
  double rho_2k = kUnknown;     ///< lag-2k
  double rho_3k = kUnknown;     ///< lag-3k
  double noise_share = kUnknown;  ///< η = 6 (ρ_2k − ρ_3k) (scheme-consistent: GLS over lags k, 2k), in [0, 1]
  SamplingVerdict verdict = SamplingVerdict::Unknown;
  double sensor_noise_sd = 0.0;  ///< white sensor noise s on x (estimated by the noisy estimator)
  double quantisation_step = 0.0;  ///< q of the grid the values lie on (vehs/core/quantisation.hpp); 0: none
};

/// How a recorded input u is applied between its samples: held (a DAC), linear, cubic
/// (Catmull–Rom) or band-limited (windowed sinc; an anti-aliased input). The likelihood, the
/// free run and simulate-vehs apply the input the way the model was fitted with it.
enum class InputInterpolation { ZeroOrderHold, Linear, Cubic, BandLimited };
inline constexpr EnumNames<InputInterpolation, 4> kInputInterpolationNames{
    {{InputInterpolation::ZeroOrderHold, "zoh"},
     {InputInterpolation::Linear, "linear"},
     {InputInterpolation::Cubic, "cubic"},
     {InputInterpolation::BandLimited, "band_limited"}}};

/// A fitted sensor noise sd is resolved when it exceeds twice its standard error (no standard
/// error: when positive). An estimate at the boundary (noise-free records: 2e-7 to 4e-5) is no
/// sensor: no automatic bias correction (likelihood/refine.cpp) and a continuous-time reading
/// in diagnose (diagnose/sampling.cpp).
inline bool measurement_noise_resolved(double sd, double stderr_) { return sd > 0.0 && !(stderr_ > 0.5 * sd); }

/// What maximum likelihood (vehs/likelihood/refine.hpp) adds to a fit: how the data were
/// observed and the figures of the fit (the model file's "likelihood" section).
struct LikelihoodFit {
  double measurement_sd = 0.0;        ///< white sensor noise on x (0: none in the model)
  std::vector<double> record_phases;  ///< harmonic_forcing phase per record (empty: shared)
  double log_likelihood = 0.0;
  double bic = 0.0;                   ///< −2 log L + k log n
  std::size_t observations = 0;
  int substeps = 0;                   ///< RK4 substeps per sampling interval of the filter
  std::string selection;              ///< "bic", "lr" or "none"
  std::string covariance_method;      ///< "observed", "fisher" or "sandwich"
  bool converged = false;
  std::string reason;                 ///< why the likelihood was used
  std::vector<std::string> parameters;  ///< free parameters (vehs/likelihood/parameters.hpp names)
  std::vector<double> values;           ///< their estimates (natural scale)
  std::vector<double> covariance;       ///< row-major, parameters × parameters
  /// The simulation-based correction of the filter's bias (vehs/likelihood/refine.hpp:
  /// RefineOptions::bias_correction_datasets): B data sets (0: not applied), the seed of the
  /// first, its largest shift in the fit's standard errors; why an automatic one was skipped.
  int bias_correction_datasets = 0;
  std::uint64_t bias_correction_seed = 0;
  double bias_correction_max_shift_se = 0.0;
  std::string bias_correction_skipped;
};

struct FitInfo {
  Estimator estimator = Estimator::Auto;  ///< the estimator used (Auto: not stated)
  int stride = 0;                         ///< its stride k (0: not stated)
  SamplingDiagnosis sampling;
  /// How the recorded input was applied in the fit (the moment estimators: held).
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  /// Set when the moment fit was refined by maximum likelihood.
  std::optional<LikelihoodFit> likelihood;
};

}  // namespace vehs
