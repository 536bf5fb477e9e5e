#pragma once
// Suspects: which catalogue effect (docs/model-file.md#effects) missing from the model would the data
// support? Issue 7: term-like effects, the dynamic forces and colored_noise.
//
// Procedure. Every record is split in time: the first (1 − holdout) of its samples train, the
// rest is held out. On the training part, identify (vehs::identify::identify, the lens's
// estimator and stride, sparsity off) fits the baseline — the model's own drift and diffusion
// terms — and, for every candidate effect not yet in the model, the baseline plus the effect's
// terms (identify::Options::effects). Each fit is then scored on the held-out rows:
//  * drift effects: the identify contrast (Itô-corrected for central kinematics, with the
//    sensor-noise corrections of the noisy estimator), whose expectation is E[(F − b2)²] up to a
//    constant, weighted per row by 1/(2·σ²(x)), σ²(x) = c·a22_base(x, 0)/h + 6s²/h⁴ — so that the
//    gain L_base − L_effect is a Gaussian log-likelihood gain in nats;
//  * velocity_dependent_noise: the Gaussian log-likelihood of the baseline drift residuals with
//    the variance c·a22(x, v̂)/h + 6s²/h⁴ of each fit (nats).
// evidence = total held-out gain (nats; positive: the effect predicts better); z = its mean over
// held-out blocks (records, or sub-blocks of few records) divided by the standard error from
// the block-to-block spread. A suspect is `significant` when z > z_threshold (default 3, about a
// 1 % family-wise level over the eight tested effects) and the gain is positive. Suspects are
// ranked by evidence. Adding more terms can only lower the held-out fit through estimation noise,
// so a model that lacks nothing gives gains ≈ −(extra terms)/2 nats and no significant suspect.
//
// Dynamic forces (impact_stop, harmonic_forcing, electromechanical_coupling): identify fits them
// on the training part (profile least squares over gap / frequency / time constant, see
// vehs/identify/dynamic.hpp); the held-out score is the same weighted drift contrast, with the
// fitted force evaluated at the held-out samples (harmonic forcing at their absolute time, the
// electromechanical state filtered along the whole record). The profile search picks the best of
// many nonlinear candidates on the training part only, so chance fits (a random spectral line, a
// gap at the largest |x|) do not carry over to the held-out part: on data without the effect the
// gain is about −(parameters)/2 nats or less. A fit that ends unphysical (k_stop ≤ 0, coupling
// < 0) is listed as untested with the reason. When the model already has dynamic effects they are
// refitted (all params free) in the baseline and in every candidate fit.
//
// Confirmation (diagnose, SuspectOptions::confirm). An OU excitation predicted from the record's
// past absorbs ANY slowly varying force the model lacks — a hidden electromechanical state, a
// forcing line, a stop — so on held-out one-step evidence colored_noise can outscore the force
// that is really there (measured on data with a hidden electromechanical state: 229.9 vs 225.1
// nats in the CI loop's data, and it led in 1 of 6 random draws; bench/results/diagnose_calibration_log.md). When the model is inadequate, one of colored_noise and the
// deterministic dynamic forces (impact_stop, harmonic_forcing, electromechanical_coupling) leads
// and is held-out significant, and the other kind is a close contender (positive evidence, not
// below the leader's by 2 paired standard errors over the blocks), diagnose refits the model
// with each contender —
// deterministic forces first, by evidence, colored_noise last — and diagnoses the refit (no
// suspects): the first whose refit is adequate is ranked first. A coloured excitation is thus
// named only when no deterministic slow force explains the data (when it is there, the refits
// with the forces stay inadequate or diverge). refit_verdict / refit_score record the outcome.
//
// colored_noise (OU excitation η): identify fits tau, intensity, the drift (GLS on Kalman
// prediction errors) and the white diffusion on the training part; on the held-out rows the
// candidate's prediction is its drift plus the excitation predicted by a Kalman filter of the
// residuals of the record's past (identify::colored_prediction, rows up to i − 2k, so the noise of
// â_i is not used), scored with the same weighted drift contrast in nats. An OU excitation is
// random, so only the predictable part counts: the gain grows with intensity/a22 and with tau/h.
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/core/user_effect.hpp"
#include "vehs/diagnose/lens.hpp"
#include "vehs/diagnose/verdict.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::diagnose {

enum class SuspectMethod {
  DriftTerms,      ///< term-like drift effect: identify with Options::effects, drift contrast
  DiffusionTerms,  ///< term-like diffusion effect: identify with Options::effects, diffusion likelihood
  DynamicForce,    ///< dynamic force (stops, forcing, hidden state): identify's profile fit, drift contrast
  ColoredExcitation,  ///< colored_noise: identify's GLS fit, drift contrast with the predicted excitation
  NotYet,          ///< dynamic effect: identify cannot fit it yet
};

struct SuspectEntry {
  EffectId id;
  SuspectMethod method;
  std::string_view note;  ///< shown for NotYet entries
};

/// One entry per catalogue effect, in catalogue order.
const std::vector<SuspectEntry>& suspect_table();

struct SuspectOptions {
  bool enabled = true;
  double holdout = 0.3;      ///< fraction at the end of every record held out
  double z_threshold = 3.0;  ///< significance of the held-out gain
  int min_blocks = 20;       ///< held-out blocks for the standard error
  bool confirm = true;       ///< confirm colored_noise against deterministic slow forces by refits (diagnose)
  std::vector<EffectId> only;  ///< empty: every effect of the table
  /// A user's own effects, tested as term-like suspects after the table's (drift terms: the drift
  /// contrast; diffusion terms only: the diffusion likelihood).
  std::vector<UserEffect> user_effects;
  ProgressCallback progress;   ///< task "suspects"; empty: none
  std::string invalid_reason() const;
};

struct Suspect {
  std::string effect;
  double evidence = 0.0;   ///< held-out log-likelihood gain, nats
  double z = 0.0;
  bool significant = false;           ///< claimed: held-out significant and the model inadequate
  bool held_out_significant = false;  ///< z > z_threshold and a positive gain, whatever the verdict
  std::string scale;       ///< "drift contrast" or "diffusion likelihood"
  std::map<std::string, double> params;         ///< the effect's fitted parameters
  std::map<std::string, double> params_stderr;  ///< their standard errors
  std::vector<std::string> terms;  ///< terms the effect added
  /// Non-empty when the fitted parameters leave the effect's domain ("quadratic_damping.c = -0.28
  /// is outside its domain (>= 0)"): such a suspect is never claimed, whatever its gain.
  std::string outside_domain;
  /// Set when the suspect was confirmed by a refit (diagnose's confirmation of close contenders):
  /// the verdict and score of the model refitted with this effect, or why the refit failed.
  std::optional<Verdict> refit_verdict;
  std::string refit_error;
  std::vector<double> block_gain;  ///< held-out gain per block (nats), for paired comparisons
  double refit_score = std::numeric_limits<double>::quiet_NaN();
};

struct SuspectReport {
  std::vector<Suspect> ranked;  ///< tested effects, by evidence (descending)
  /// Effects not tested, with the reason (already in the model, not yet supported...).
  std::vector<std::pair<std::string, std::string>> untested;
  double baseline_heldout_rows = 0.0;
  int blocks = 0;
  std::string note;  ///< non-empty when the suspects could not be evaluated at all
  /// Non-empty when the held-out evidence is not a test on these data (a likelihood fit, coarse
  /// sampling, correlated rounding): why. The ranking is then shown, never claimed.
  std::string set_aside;
};

/// z of a held-out gain: the mean over blocks divided by its standard error from the
/// block-to-block spread (0 with fewer than 2 blocks or no spread).
double block_z(const std::vector<double>& gain);

/// The outcome of a suspect's confirming refit as text: "adequate", "inadequate",
/// "refit failed: <why>", or empty when it was not refitted.
std::string refit_text(const Suspect& suspect);

/// The method of a catalogue effect in the suspect table (NotYet when it has none).
SuspectMethod suspect_method(EffectId id);
/// The method of a suspect by name: a catalogue effect's, else (a user effect) DriftTerms.
SuspectMethod suspect_method(const std::string& effect);

/// identify's options for refitting `model` (its own terms, its dynamic effects with all params
/// free, sparsity off) as seen through `lens`: the baseline of the suspects; add an effect to
/// options.effects to fit a candidate.
identify::Options refit_options(const Model& model, const Lens& lens);

/// Fits and scores the suspects (see the header comment). Errors of the fits (e.g. too short
/// records) are returned in `note` rather than thrown.
SuspectReport rank_suspects(const Model& model, const Dataset& data, const Lens& lens,
                            const SuspectOptions& options);

}  // namespace vehs::diagnose
