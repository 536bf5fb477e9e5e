#pragma once
// Confirmation of the suspects by refits judged out of sample (issue 13, real data).
//
// A score test (score_suspects.hpp) or a held-out one-step gain (suspects.hpp) says that the
// model plus an effect explains the data better NEAR the model. When the model is misspecified
// in a way outside the catalogue (Silverbox: z ≈ 3500 for velocity_dependent_noise, 240–500 for
// the damping forms), every effect correlated with the misfit lights up, and refits with them
// make the model worse where it matters to the user (its free-run RMSE on the benchmark's test
// records rose from 0.41 to 6.6 mV). So before an effect is recommended, diagnose refits the
// model with it and checks that the refit predicts data it has not seen:
//
//  * split: the first (1 − holdout) of every record trains, the rest is held out and cut into
//    pieces (at least `blocks` in all, each ≥ 200 samples); the data are the leading whole
//    records up to max_samples. Nothing outside the user's data is used.
//  * refit: the baseline (the model's own terms and dynamic effects, all free) and the baseline
//    plus each candidate are refitted on the training part the way the model was fitted —
//    identify's moment fit through the diagnosis's lens (suspects.hpp: refit_options), then,
//    when the model file says the model was refined by maximum likelihood (Model::fit's
//    likelihood section), vehs::likelihood::refine with the same input interpolation and
//    measurement noise, the support fixed (no selection).
//  * criteria on the held-out pieces: (a) for a model fitted by maximum likelihood, the
//    one-step log-likelihood of the continuous–discrete filter (vehs/likelihood/filter.hpp; each
//    piece a block started from its first sample); for a moment fit, the held-out suspects'
//    drift contrast (suspects.hpp: identify refits on the same training share, scored through
//    the lens — the filter assumes a continuous-time model, which a moment fit to
//    scheme-consistent data is not: on such data its innovations had variance 1.75 and lag-1
//    correlation −0.27); and, for a driven model (a drive term u), (b) the free-run mean squared error of
//    x (vehs/likelihood/free_run.hpp; started from each piece's measured state, the first
//    `free_run_skip` samples left out). The gain of the refit with the effect over the refitted
//    baseline is paired piece by piece; z = its mean over the pieces / the standard error from
//    their spread (block_z). Confirmed: every criterion improves by more than z_threshold
//    standard errors. A refit that fails (an estimate outside the catalogue's domain, a filter
//    or free run that diverges) is not confirmed, with the reason.
//
// For a model fitted by maximum likelihood, the baseline's held-out innovations (the filter's
// standardised prediction errors) also say what the misfit looks like when no catalogue effect
// explains it (ResidualSignature; empty for a moment fit).
#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/diagnose/lens.hpp"
#include "vehs/diagnose/suspects.hpp"

namespace vehs::diagnose {

struct ConfirmationOptions {
  /// Off by default in the library (diagnose-vehs turns it on): every candidate costs a refit.
  bool enabled = false;
  double holdout = 0.3;         ///< share at the end of every record held out
  int blocks = 8;               ///< held-out pieces in all (at least; each ≥ 200 samples)
  double z_threshold = 2.0;     ///< an improvement must exceed this many standard errors
  double max_samples = 2.5e5;   ///< whole records, in order, up to this many samples (0: all)
  int max_effects = 8;          ///< candidates refitted at most (the most significant first)
  std::size_t free_run_skip = 50;  ///< samples of each piece left out of the free-run error
  std::string invalid_reason() const;
};

/// One candidate effect: its refit and the held-out comparison with the refitted baseline.
struct Confirmation {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::string effect;           ///< catalogue name
  bool per_record_phase = false;  ///< harmonic_forcing refitted with one phase per record
  std::string evidence;         ///< why it was a candidate ("score test z = 3527.2", ...)
  bool confirmed = false;
  double loglik_gain = kNaN;    ///< held-out one-step log-likelihood, refit − baseline (nats)
  double loglik_z = kNaN;
  double rmse_baseline = kNaN, rmse_effect = kNaN;  ///< held-out free-run RMSE (driven models)
  double rmse_z = kNaN;         ///< z of the reduction of the mean squared free-run error
  std::map<std::string, double> params, params_stderr;  ///< the effect's parameters in the refit
  std::string error;            ///< the refit or its evaluation failed: why
  std::string reason;           ///< one line: why (not) confirmed
};

/// What the refitted baseline's held-out innovations z_k = (x_k − x̂_k)/√S_k show. z-values
/// are of the statistic against its law for white N(0, 1) innovations (NaN: not computed).
struct ResidualSignature {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::size_t samples = 0;
  double variance = kNaN;              ///< mean z² (1 for a calibrated filter)
  double lag1 = kNaN, lag1_z = kNaN;   ///< lag-1 autocorrelation: memory the model lacks
  double excess_kurtosis = kNaN, kurtosis_z = kNaN;  ///< heavy tails (se √(24/n))
  double heteroscedasticity = kNaN, heteroscedasticity_z = kNaN;  ///< corr(z², ŷ²) or corr(z², x̂²)
  std::string heteroscedastic_in;      ///< "velocity" or "displacement"
  double input_correlation = kNaN, input_z = kNaN;  ///< largest corr(z_k, u_{k−lag}) over lags
  int input_lag = 0;
  double line_frequency = kNaN, line_z = kNaN;  ///< largest averaged periodogram ordinate (rad/time), Bonferroni
  std::string summary;                 ///< one line: the significant features (|z| > 4), largest first
};

struct ConfirmationReport {
  bool ran = false;
  std::string note;             ///< why it did not run, or what limited it
  std::string criterion;        ///< one line
  bool driven = false;          ///< the free-run criterion was used
  std::size_t train_samples = 0, heldout_samples = 0;
  int pieces = 0;
  double baseline_loglik = Confirmation::kNaN;  ///< held-out, nats
  double baseline_rmse = Confirmation::kNaN;    ///< held-out free run (driven models)
  std::vector<Confirmation> effects;            ///< in the order tried
  ResidualSignature residuals;
  double seconds = 0.0;
};

/// A candidate: the effect and why it is one.
struct Candidate {
  EffectId id;
  std::string evidence;
  bool per_record_phase = false;  ///< harmonic_forcing with one phase per record
};

/// Refits and judges the candidates (see the header comment). Errors of single refits go to
/// the candidate's `error`; a baseline that cannot be refitted or evaluated goes to `note`.
ConfirmationReport confirm_effects(const Model& model, const Dataset& data, const Lens& lens,
                                   const std::vector<Candidate>& candidates, const SuspectReport& heldout,
                                   const ConfirmationOptions& options);

}  // namespace vehs::diagnose
