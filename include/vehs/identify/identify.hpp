#pragma once
// Identification of dX = Y dt, dY = b2(X, Y, u) dt + sqrt(a22(X, Y)) dB from displacement
// records (docs/measurements.md) sampled at a uniform interval Δt.
//
// Estimators (Options::estimator):
//  * paper    — the seed paper's method: forward differences y_i = (x_{i+1} − x_i)/Δt,
//               b_i = (y_{i+1} − y_i)/Δt regressed on φ(x_i, y_i); raw Kramers–Moyal diffusion
//               a22 ≈ (y_{i+1} − y_i)²/Δt fitted by ordinary least squares. For comparison only:
//               the raw diffusion carries Δt·b2² (2Q about half its true value even on the
//               paper's own data), and on continuous-time records β comes out ≈ 1/3 low.
//  * forward  — forward kinematics as above, diffusion from the drift residuals
//               a22 ≈ Δt·(b − F̂)², by weighted least squares. Consistent (bias O(Δt)) for
//               records produced by an explicit one-step scheme at the recorded step (the
//               paper's synthetic data), where the noise of b_i is independent of (x_i, y_i).
//  * uli      — underdamped Langevin inference (Brückner, Ronceray & Broedersz, PRL 124,
//               060603, 2020) for a sensor sampling a continuous process: on a stride of k
//               samples (h = kΔt), v̂ = (x_{i+k} − x_{i−k})/2h, â = (x_{i+k} − 2x_i + x_{i−k})/h².
//               Given the past, â's noise has covariance a22/2 with v̂ (Stein's lemma), so
//               ⟨â φ(x, v̂)⟩ = ⟨b2 φ⟩ + ½⟨a22 ∂_vφ⟩ + O(h): the drift solves the corrected
//               normal equations G c = Σ φ â − ½ Σ ∂_vφ a22. Without this Itô correction the
//               damping comes out ≈ 0 (stationarity makes Σ â v̂ ≈ 0). Diffusion:
//               a22 = (3/2)·h·E[(â − F)² | x], by weighted least squares (â's noise covaries
//               with F(x, v̂) and with the window average of b2 alike, h²/2 each, so the ∂_vF
//               cross-terms cancel in E[(â − F)²]). Consecutive residuals
//               (lag k) are correlated +1/4; standard errors account for it. The O(h²) error
//               of the central difference, (h²/12)·x⁗, is removed from the target with x⁗
//               from a pilot drift (deterministic part; exact for drifts linear in v).
//  * noisy    — ULI tolerating white sensor noise of standard deviation s on x. The stride k is
//               chosen so that the noise part 6s²/h⁴ of â's variance is at most comparable to
//               the process part (2/3)a22/h; s² is estimated from the lag-2k autocovariance
//               of the residuals (which only noise feeds: s² = h⁴·E[r_i r_{i+2k}]); the drift
//               Gram matrix is corrected for the errors-in-variables variance s²/2h² of v̂ and the
//               −2s²/h² covariance of â with x_i; the diffusion uses the noise-free combination
//               a22 = (12/11)·h·E[r_i² + 1.5 r_i r_{i+k} | x]. Limits: white, homoscedastic
//               noise; the O(h) bias of ULI grows with the stride (so the noise level must
//               stay well below the displacement change over ~0.1 periods); x-noise in the
//               Gram matrix (relative s²·(∂_xφ)²/φ²) is neglected.
//  * auto     — (default) measures the sampling from ULI residuals of a pilot fit on a
//               subsample: ρ_k (lag-k autocorrelation) ≈ 0 for data from an explicit scheme at
//               the recorded step, ≈ +1/4 for a sensor sampling a continuous process; and
//               ρ_2k ≈ η/6 where η is the share of white sensor noise in â's variance. Picks
//               noisy when η > 0.05, else uli when ρ_1 + (2/3)η > (1 − η)/8, else forward; the
//               choice and the figures are reported in the model file. Values on a grid (ADC
//               counts, printouts) are a sensor's: noisy when the rounding makes ≥ 1 % of â's
//               variance and the lags read no continuous process, and noisy instead of uli when
//               12× the rounding's share (an ADC's own noise of up to 1 LSB beside it, which the
//               ULI target would take for diffusion) exceeds a22's relative SE √(2/rows).
//               After a ULI fit chosen so, the residuals' lag-k autocorrelation over all rows
//               reads white noise the pilot cannot resolve: ρ_k = 1/4 − (11/12)η; when it is
//               below 1/4 by more than 4 of its standard errors (√(0.83κ/rows), κ the
//               residuals' E[r⁴]/(3E[r²]²)), the data are refitted with noisy (the estimator's
//               reason says so).
//  * likelihood — not an estimator of this area: identify-vehs's `estimator: "likelihood"` (or a
//               `likelihood` block) refines the auto moment fit by maximum likelihood at the
//               data's own sampling (vehs/likelihood/refine.hpp: same support first, then
//               backward selection by BIC or a likelihood-ratio test; standard errors from the
//               observed information, Fisher or a sandwich). With auto the tool does so whenever
//               vehs/likelihood/adequacy.hpp cannot vouch for the expansions above (ω̂Δt ≥ 0.2
//               with a bias (ω̂Δt)²/12 above the best relative SE, or a recorded input with
//               ω̂Δt ≥ 0.1). Model::fit->likelihood then holds what the refinement adds.
//
// Sparse regression (Options::sparsity): SSR removing at each step the term with the smallest
// t-ratio (or |coef|, as in the paper), the step chosen by BIC with the measured long-run
// variance factor (default; see Criterion for why) or by blocked cross-validation over
// contiguous time (one-standard-error rule); or STLSQ. Drift and diffusion are selected
// separately; terms of requested effects are never removed. CV contrasts, BIC and coefficients
// of every step are reported.
//
// Diffusion fit: weighted least squares of the diffusion target z on ψ with weights
// 1/a22(x, v)² (Var z ∝ a22² for Gaussian increments), a22 taken from a pilot fit on a
// subsample and floored at 5 % of its mean; the weights affect efficiency only, not consistency.
//
// Statistics are streamed: one pass per stage over the records (in parallel, deterministic
// reduction order), accumulating Gram matrices per fold; memory does not grow with the data.
// Passes: pilot (subsample) → drift → residuals/diffusion → scores (standard errors).
//
// Standard errors: sandwich estimator of the joint estimating equations of drift and diffusion
// coefficients, J⁻¹ Ω J⁻ᵀ, with Ω the covariance of score sums over contiguous blocks of
// `se_block` samples (batch means: robust to the MA residuals, heteroscedasticity and the
// dependence of the drift's Itô correction on the diffusion estimate). The uncertainty of the
// estimated sensor-noise variance (noisy) is not propagated.
//
// Units: time in the units of the records' t column; coefficients of b2 = Σ c·φ and
// a22 = Σ q·ψ as in docs/model-file.md (a22 is a variance rate, 2D in the paper's notation).
// The fit runs on the data scaled to O(1) by powers of ten (vehs/core/scaling.hpp:
// natural_scales) and the model is converted back, so the same record in m, mm or
// non-dimensional gives the same model up to the unit conversion. A standard error that is not
// finite is an error naming the parameter. Model::covariance holds the sandwich covariance of
// the term fit (empty after a dynamic-effect fit, whose errors are reported per parameter).
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/enum_names.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/core/user_effect.hpp"
#include "vehs/identify/regression.hpp"
#include "vehs/identify/report.hpp"

namespace vehs::identify {

using vehs::Estimator;  // (vehs/core/fit_info.hpp)
using vehs::kEstimatorNames;

struct Options {
  std::vector<Term> drift_library = paper_drift_library(11, 3);
  std::vector<Term> diffusion_library = paper_diffusion_library(4);
  /// Effects of docs/model-file.md#effects. Term-like ones add their terms, kept through selection.
  /// Dynamic ones (impact_stop, harmonic_forcing, electromechanical_coupling) are fitted by
  /// profile least squares (vehs/identify/dynamic.hpp); params present in an entry are held
  /// fixed. colored_noise is fitted from the residual autocovariance with the drift refitted by
  /// GLS on Kalman prediction errors (dynamic.hpp); it cannot yet be combined with the other
  /// dynamic effects or with sensor noise (one-line error).
  std::vector<Effect> effects;
  /// A user's own effects (vehs/core/user_effect.hpp): their terms join the dictionaries and are
  /// kept through selection; Report::user_effect_params gives their parameters.
  std::vector<UserEffect> user_effects;
  /// Known force per sample (aligned with Dataset::x), subtracted from the acceleration
  /// target; used by the dynamic-effect fit (not with dynamic effects in `effects`).
  const std::vector<double>* known_force = nullptr;
  /// Further terms never removed by the sparse regression.
  std::vector<Term> keep_drift, keep_diffusion;

  Estimator estimator = Estimator::Auto;
  int stride = 0;  ///< ULI stride k (0: 1 for uli, chosen from the noise level for noisy)
  /// uli/noisy: remove the O(h²) error of the central second difference, (h²/12)·x⁗ with x⁗
  /// from a pilot drift fit (see identify.cpp: FourthDerivative).
  bool discretization_correction = true;

  Sparsity sparsity = Sparsity::Ssr;
  SsrRule ssr_rule = SsrRule::TRatio;  ///< the paper estimator defaults to AbsCoef (see below)
  bool ssr_rule_set = false;           ///< false: paper → abs_coef, others → t_ratio
  Criterion criterion = Criterion::Bic;
  int folds = 10;                      ///< contiguous time blocks of every record
  double stlsq_threshold = 0.05;       ///< |coef| threshold of STLSQ (on the coefficients of the data scaled to O(1))

  std::size_t se_block = 0;        ///< batch length of the standard errors (0: automatic)
  std::size_t pilot_samples = 250000;  ///< rows of the pilot fits (sampling diagnosis, weights)
  double noise_share_target = 0.95;  ///< noisy: share of sensor noise in â's variance aimed at by the stride
  ProgressCallback progress;  ///< task "identify": the streaming passes; empty: none

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

/// The sampling rule shared by identify's pilot and diagnose, from the autocorrelations of ULI
/// drift residuals at stride k over `rows` rows. For a clean continuous-time process the ULI
/// noise is correlated over lags < 2k only (ρ_k ≈ 1/4, ρ_2k = ρ_3k = 0); an explicit scheme at
/// the recorded step gives ρ_k ≈ 0; white sensor noise of share η adds −(2/3)η at lag k and η/6
/// at lag 2k but nothing at lag 3k; a smooth force the residuals still carry (an OU excitation,
/// a hidden state, a forcing line) adds about the same to lags k, 2k and 3k. So
///   η = 6 (ρ_2k − ρ_3k), clamped to [0, 1];   continuous: (ρ_k − ρ_3k) + (2/3)η > (1 − η)/8;
/// and the data are "noisy" when η > 5 % and η exceeds 3 of its standard errors (≈ 6√2/√rows:
/// short data do not invent sensor noise). Without the lag-3k reference an OU excitation with
/// τ = 10h read as 40 % sensor noise.
/// Scheme-consistent data (not continuous) have a known lag-k base, 0, so there η is re-read
/// from BOTH differences d_k = ρ_k − ρ_3k ≈ −(2/3)η and d_2k = ρ_2k − ρ_3k ≈ η/6 by generalised
/// least squares (their covariance ≈ [[2, 1], [1, 2]]/rows for white residuals): standard error
/// 1.60/√rows instead of 8.5/√rows, and a lag-2k excess that lag k contradicts is not read as
/// noise. With lag 2k alone a 3-sigma excess at lag 2k (d_2k = 0.0097 on 2·10⁵ rows, ρ_k ≈ 0)
/// read as 5.9 % sensor noise and the true model's diagnosis failed every residual component
/// (bench/results/diagnose_calibration_log.md, calibration matrix: 200 × 1000, seed 5).
/// Where the midpoint rule reads "not continuous" but ρ_k − ρ_3k lies more than 5 standard errors
/// (√(2/rows)) above 0, no explicit scheme explains it (noise and coarse dynamics only lower lag
/// k): the data are a sensor on a continuous process whose noise the lag-2k reading alone did not
/// resolve, and η is read from both differences under that hypothesis, d_k ≈ 1/4 − (11/12)η and
/// d_2k ≈ η/6 (a rig in metres at 40 samples per period with 1 % sensor noise, 20 000 samples:
/// ρ_k 0.039, η ≈ 0.19 read as forward before, the stiffness 4 SE and the friction 9–10 SE off).
struct SamplingRule {
  double noise_share = 0.0;
  bool noisy = false, continuous = false;
  SamplingVerdict verdict = SamplingVerdict::SchemeConsistent;
};
SamplingRule sampling_rule(double rho_k, double rho_2k, double rho_3k, double rows);

struct Result {
  /// Coefficients with standard errors, the fitted dynamic effects, and Model::fit (the
  /// estimator used, its stride and the sampling diagnosis).
  Model model;
  Report report;  ///< how: estimator choice, residuals, selection paths, conditioning, timing
};

/// Identifies the model from `data` (all records must share one sampling interval).
/// Throws vehs::Error for invalid options, unusable records (too short, constant, NaN) naming
/// the record, or an ill-conditioned dictionary naming the collinear terms.
Result identify(const Dataset& data, const Options& options);

/// Physical parameters of term-like effects from fitted coefficients (e.g. mu = −coef of
/// sign(y)), with standard errors (one Effect per entry of `effects`).
std::vector<Effect> effect_parameters(const Model& model, const std::vector<Effect>& effects);

/// The terms no selection may remove: Options::keep_drift / keep_diffusion and the terms of the
/// requested term-like effects and user effects (for the likelihood's selection as for identify's).
EffectTerms kept_terms(const Options& options);

}  // namespace vehs::identify
