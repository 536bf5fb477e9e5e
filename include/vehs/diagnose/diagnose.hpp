#pragma once
// Model adequacy: how well does a model (docs/model-file.md) reproduce measured displacement
// records, and where exactly does it fail?
//
// Method (see hypothesis.hpp and lens.hpp for the statistics):
//  1. The data are looked at through a lens — identify's finite-difference kinematics at the
//     model's stride — giving whitened one-step residuals r = (â − b2)/sqrt(c·a22/h) per row.
//  2. For every data record the model is simulated R times ("twins") with the record's duration,
//     sampling interval, initial displacement and velocity, drive and measurement process (the
//     sampling diagnosis: scheme-consistent data → the paper's rk4_euler at the recorded step;
//     continuous-time data → taylor15 on substeps with ρ·h ≤ 0.02, ρ the model's fastest
//     linearised rate, so that the twins are exact at any Δt (ω·Δt ≈ 1 included); noisy data →
//     plus white sensor noise). A model fitted by the likelihood (its file's "likelihood"
//     section) is a continuous-time SDE observed with white noise of measurement_sd: its twins
//     are simulated so, whatever the data's sampling diagnosis reads. Every component below
//     compares data with twins through the same lens, so an expansion in Δt in the lens (the
//     whitening variance c·a22/h, the kinematics) is a choice of statistic, not an approximation
//     of the test: the calibration holds at coarse sampling (bench/results/diagnose_calibration_log.md).
//     Dynamic effects are simulated with the twins: harmonic forcing in the records' absolute
//     time (t0 of each record), the electrical state from 0 and the coloured excitation from its
//     stationary law at every record's start (as vehs::sim does). For a model with dynamic
//     effects the sampling diagnosis uses the model's own residuals (see diagnose.cpp).
//  3. The IDENTICAL statistics code runs on data and twins, per unit (record, or time block of
//     a record when there are fewer than min_units records), and the units are compared in pairs:
//       one_step           residual mean and variance in (x, v̂) bins (the failure map);
//       drift_shape        residual mean times low-order functions of (x, v̂) (polynomials to third
//                          order, sign(v̂), v̂|v̂|): smooth drift misfits — missing damping forms,
//                          stiffness terms — that the bin-wise map dilutes over hundreds of bins;
//       noise_shape        squared residual times polynomials of (x, v̂) to second order: a22 with
//                          the wrong dependence on x or v̂;
//       residual_spectrum  band-averaged log spectrum of the residuals (memory, periodic forcing);
//       pdf                occupation of coarse (x, v̂) cells (shape of p(x, v̂));
//       power              log E[X²] and log E[v̂²] (v̂ the lens velocity: the mean power);
//       wells              probability per well and well-to-well transition rate (multi-well
//                          models; wells from the model's potential, transitions counted with
//                          hysteresis between the wells' cores);
//       acf                band-averaged log power spectrum of x (the Fourier pair of its ACF);
//       residual_lines     the largest single-frequency excess of the residual spectrum (a line:
//                          periodic forcing), one-sided t over units, Bonferroni over the bins;
//     (residual_spectrum, power, acf, residual_lines: a log on the data's side against the MEAN
//     of the R twins' logs — not the log of their mean, which by Jensen sits about ½·CV²·(1 − 1/R)
//     higher and made a true model inadequate at 288 records; src/diagnose/unit_stats.hpp)
//       suspects           the largest held-out z of the catalogue effects the model lacks (a test
//                          against named alternatives, Bonferroni over the effects; see 5.).
//  4. Each component is a calibrated test with a p-value; its size is the excess normalised
//     chi-square max(0, χ²/dof − 1). score = Σ sizes (lower is better; ≈ 0 for an adequate
//     model; comparable between models fitted to the same data). verdict = inadequate when any
//     component's p-value is below alpha/(number of components) (Bonferroni, family-wise alpha).
//  5. Suspects (suspects.hpp): every catalogue effect not yet in the model is fitted on the first
//     part of every record and scored on the held-out rest. Their refits are moment estimators
//     (expansions in Δt): for a likelihood fit or at ω̂·Δt ≥ 0.2 (0.1 with an input) they are not
//     a test of the model (component unavailable, nothing claimed); the score tests are.
//  6. Confirmation (confirmation.hpp, Options::confirm): for an inadequate model every
//     significant suspect is refitted the way the model was fitted and must predict held-out
//     pieces of the records better before it is recommended (Result::recommended); when none
//     is, Result::conclusion says what fails and what the held-out innovations show — "the
//     misfit is outside the catalogue" when the model fails far beyond the threshold.
//
// Units: time in the units of the records' t column; x as recorded; v̂ in x per time unit.
// Memory: the data, one twin replicate at a time, and O(units × bins) statistics (the spectra
// O(units × replicates × spectrum length)).
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/enum_names.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/core/user_effect.hpp"
#include "vehs/diagnose/confirmation.hpp"
#include "vehs/diagnose/hypothesis.hpp"
#include "vehs/diagnose/lens.hpp"
#include "vehs/diagnose/score_suspects.hpp"
#include "vehs/diagnose/suspects.hpp"
#include "vehs/diagnose/verdict.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::diagnose {

enum class LensChoice { Auto, Forward, Central };

/// Whether the tests of the stationary and x-spectrum components include the model's parameter
/// uncertainty (estimated by refitting the model's terms on pseudo-data simulated from it and
/// resimulating with common random numbers; see hypothesis.hpp). auto: on when the model file
/// reports standard errors (it was fitted, presumably to these data).
enum class ParameterUncertainty { Auto, On, Off };
inline constexpr EnumNames<ParameterUncertainty, 3> kParameterUncertaintyNames{
    {{ParameterUncertainty::Auto, "auto"}, {ParameterUncertainty::On, "on"}, {ParameterUncertainty::Off, "off"}}};
inline constexpr EnumNames<LensChoice, 3> kLensNames{
    {{LensChoice::Auto, "auto"}, {LensChoice::Forward, "forward"}, {LensChoice::Central, "central"}}};

struct Options {
  // ---- lens
  LensChoice lens = LensChoice::Auto;  ///< auto: the model's estimator (model file), else the data's sampling
  int stride = 0;                      ///< central stride (0: the model's, else 1)
  /// < 0: from the model file (likelihood.measurement_sd, else sampling.sensor_noise_sd) or the
  /// sampling diagnosis; > 0: the data are noisy continuous-time records (twins so).
  double sensor_noise = -1.0;
  // ---- twins
  int replicates = 0;                  ///< twins per record; 0: enough for >= 2e6 twin samples (1..8)
  bool twin_scheme_auto = true;
  sim::Scheme twin_scheme = sim::Scheme::Rk4Euler;
  int twin_substeps = 0;               ///< 0: 1 for scheme-consistent data, else ρ·h ≤ 0.02 (≥ 10; twins.hpp)
  std::uint64_t seed = 1;
  // ---- statistics
  int map_bins_x = 16, map_bins_v = 16;  ///< one-step map
  double min_bin_count = 200;            ///< rows per side for a bin to enter the one-step test
  int min_units = 32;                    ///< fewer records: records are cut into time blocks
  int residual_lags = 64;                ///< residual ACF lags (rows)
  double alpha = 0.01;                   ///< family-wise level of the verdict
  /// Sampling interval the user expects (config `dt`): an error when the records disagree.
  double expected_dt = 0.0;
  /// Error when the model file says it was identified at another sampling interval.
  bool check_model_sampling = true;
  // ---- the model's parameter uncertainty
  ParameterUncertainty parameter_uncertainty = ParameterUncertainty::Auto;
  int parameter_draws = 8;                 ///< refits (each: simulate, identify, resimulate)
  double parameter_fit_samples = 2e6;      ///< samples of each refit (the covariance is rescaled)
  // ---- model-side reference
  bool fpk = true;                     ///< stationary FPK density of the model as a reference
  int fpk_cells = 160;                 ///< per axis
  // ---- suspects
  /// A user's own effects (vehs/core/user_effect.hpp), tested as suspects beside the catalogue's:
  /// the same score test, held-out refit, confirmation and recommendation by name.
  std::vector<UserEffect> user_effects;
  SuspectOptions suspects;
  /// The suspects use whole records, in order, up to this many samples (their refits of dynamic
  /// effects are the slowest part of a run; 0: all data).
  double suspect_samples = 4e6;
  /// The likelihood's score tests of every effect the model lacks, on all the data (up to
  /// score_suspects.max_samples): score_suspects.hpp; a component of the verdict when enabled.
  /// Off by default in the library (diagnose-vehs turns it on): it costs a few filter passes.
  ScoreSuspectOptions score_suspects{false};
  /// When the model is inadequate, the significant suspects (score tests and held-out) are
  /// refitted and judged on held-out pieces of the records before any is recommended
  /// (confirmation.hpp). Off by default in the library (diagnose-vehs turns it on).
  ConfirmationOptions confirm;
  /// Tasks in order: "diagnose setup", "diagnose" (the twins), "diagnose tests", "parameter draws",
  /// "diagnose curves and fpk", "suspects", "score tests", "contender refits", "confirmation refits"
  /// (the stages that run); those of unknown length report their elapsed time. Empty: none.
  ProgressCallback progress;

  std::string invalid_reason() const;
};

/// One test component of the verdict.
struct Component {
  std::string name;
  std::string what;  ///< one line: what is compared
  TestResult test;
};

/// One bin of the one-step map (x, v̂).
struct MapBin {
  double x = 0.0, v = 0.0;              ///< bin centre
  double n_data = 0.0, n_twin = 0.0;    ///< rows (twin: per replicate)
  double mean_data = 0.0, mean_twin = 0.0, z_mean = 0.0;
  double var_data = 0.0, var_twin = 0.0, z_var = 0.0;    ///< z of log(var_data/var_twin)
  double kurt_data = 0.0, kurt_twin = 0.0, z_kurt = 0.0;
  bool used = false;                    ///< enough rows on both sides
};

struct OneStepMap {
  int nx = 0, nv = 0;
  double x_lo = 0, x_hi = 0, v_lo = 0, v_hi = 0;  ///< rows outside go to the edge bins
  std::vector<MapBin> bins;                      ///< bins[i * nv + j], i over x
  std::vector<int> worst;                        ///< indices of the largest |z_mean|, descending
  /// Where the failure is: mean of z² over the used bins of every v column / x row, for the
  /// residual mean (z_mean) and log-variance (z_var); NaN where no bin is used. ≈ 1 everywhere
  /// for an adequate model.
  std::vector<double> v_profile_mean, v_profile_var, x_profile_mean, x_profile_var;
};

/// A curve of the data and its twins with standard errors from the spread over units.
struct Curve {
  std::vector<double> at;  ///< abscissa (x, lag time, frequency)
  std::vector<double> data, data_se, twin, twin_se;
  std::vector<double> reference;  ///< e.g. the FPK marginal (empty when unavailable)
};

struct Quantity {
  std::string name;
  double data = 0.0, data_se = 0.0, twin = 0.0, twin_se = 0.0;
  double z = 0.0;  ///< paired z of data − twin
  double reference = std::numeric_limits<double>::quiet_NaN();  ///< FPK (stationary) value
};

struct WellInfo {
  double x_min = 0.0, lo = 0.0, hi = 0.0;     ///< range (±inf at the ends)
  double core_lo = 0.0, core_hi = 0.0;        ///< core used for transitions
};

struct SamplingInfo {
  SamplingVerdict data_verdict = SamplingVerdict::Unknown;   ///< the data's diagnosis (Unknown: it failed)
  SamplingVerdict model_verdict = SamplingVerdict::Unknown;  ///< what Model::fit says (Unknown: nothing)
  Estimator model_estimator = Estimator::Auto;               ///< estimator of Model::fit (Auto: not stated)
  double data_dt = 0.0, model_dt = 0.0;                      ///< model_dt 0: not stated
  double sensor_noise_sd = 0.0; ///< used by the lens and the twins
  sim::Scheme twin_scheme = sim::Scheme::Rk4Euler;
  int twin_substeps = 1;
  int replicates = 1;
};

struct Result {
  Verdict verdict = Verdict::Adequate;
  bool adequate() const { return verdict == Verdict::Adequate; }
  double score = 0.0;
  /// Expected score of an adequate model with the same components:
  /// Σ E[max(0, χ²_k/k − 1)] = Σ [P(χ²_{k+2} > k) − P(χ²_k > k)] (a reading aid for `score`).
  double score_expected_adequate = 0.0;
  std::vector<Component> components;
  double threshold = 0.0;  ///< per-component p-value threshold (alpha / components)
  Lens lens;
  SamplingInfo sampling;
  std::size_t records = 0, units = 0, rows = 0, samples = 0;
  std::string unit_kind;  ///< "records" or "time blocks (n per record)"
  int parameter_draws = 0;                ///< refits behind the parameter uncertainty (0: not used)
  std::size_t parameter_fit_samples = 0;  ///< samples per refit
  OneStepMap map;
  Curve residual_acf, residual_psd, px, x_acf, x_psd;
  /// p(x, v̂) on a grid (row-major, i over x) for data and twins.
  int pxy_nx = 0, pxy_nv = 0;
  double pxy_x_lo = 0, pxy_x_hi = 0, pxy_v_lo = 0, pxy_v_hi = 0;
  std::vector<double> pxy_data, pxy_twin;
  double hellinger_px = 0.0, hellinger_pxy = 0.0;            ///< data vs twins
  double hellinger_px_null = -1.0, hellinger_pxy_null = -1.0;  ///< twin vs twin (R >= 2), else −1
  std::vector<Quantity> quantities;  ///< E[X^2], E[v^2], well probabilities, transition rate
  std::vector<WellInfo> wells;
  std::string fpk_note;  ///< why the FPK reference is missing, or its grid
  SuspectReport suspects;
  ScoreSuspectReport score_suspects;
  ConfirmationReport confirmation;
  /// The effects diagnose recommends adding: with Options::confirm, the confirmed ones (the
  /// largest held-out gain first); without
  /// it, every significant suspect (score tests, then held-out). Empty for an adequate model.
  std::vector<std::string> recommended;
  /// The user's effects that were suspects (Options::user_effects): what a recommended user
  /// effect's name stands for.
  std::vector<UserEffect> user_effects;
  /// Inadequate at a significance far beyond the threshold (smallest component p below
  /// 1e-6 × threshold), the suspects were refitted, and none was confirmed.
  bool outside_catalogue = false;
  /// One line: "adequate", "inadequate — add …", "inadequate — the misfit is outside the
  /// catalogue: …" (what fails and what the held-out innovations show), or "inadequate — …".
  std::string conclusion;
  std::vector<std::string> warnings;
  std::vector<std::pair<std::string, double>> timings;  ///< seconds per stage, in order
};

/// Diagnoses `model` against `data`. Throws vehs::Error (one line) for invalid options, a model
/// that cannot be evaluated (no diffusion, a22 <= 0 where the data are, a drive term without a
/// drive column), records whose sampling interval differs from expected_dt or from the interval
/// the model was identified at, or too little data.
Result diagnose(const Model& model, const Dataset& data, const Options& options);

}  // namespace vehs::diagnose
