#pragma once
// The fit's likelihood step: the decision to refine the moment fit by maximum likelihood (on
// request, or when vehs/likelihood/adequacy.hpp cannot vouch for the expansions), its starts
// (vehs/fit/likelihood_starts.hpp) and the refined model with its typed FitInfo::likelihood.
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/fit/likelihood_starts.hpp"
#include "vehs/likelihood/adequacy.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs {

/// When the likelihood refines the moment fit: on request (Always), never, or when the sampling
/// cannot vouch for the moment estimators (Auto).
enum class LikelihoodUse { Auto, Always, Never };

/// B of `bias_correction: "auto"` (the default): B data sets when the final fit estimates the
/// measurement noise (and has one shared harmonic phase), else none; skipped, not thrown, when
/// the estimate cannot be simulated (RefineOptions::bias_correction_auto).
inline constexpr int kAutoBiasCorrectionDatasets = 8;

struct LikelihoodSettings {
  LikelihoodSettings();  ///< the defaults: auto use, selection, observed information, auto bias correction
  LikelihoodUse use = LikelihoodUse::Auto;
  likelihood::RefineOptions options;
  /// `input: "auto"` (the default): how a recorded input was applied is read from its spectrum
  /// (vehs/likelihood/input_reading.hpp) instead of options.filter.input, then decided by the
  /// likelihood: the start fitted briefly under zoh and under band_limited, the higher log L kept
  /// (records of at least 16 samples; the reason names both).
  bool input_auto = true;
  /// The start of the refinement besides the moment fit's coefficients: the sensor noise (NaN:
  /// the moment fit's), one forcing phase per record and the effects' parameters (each replaces the
  /// moment fit's effect of that id) — a refit of a model already fitted starts where it was.
  double start_measurement_sd = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> start_record_phases;
  std::vector<Effect> start_effects;
  /// false: the moment fit's FitInfo is kept (without a likelihood section) and its standard
  /// errors are the refinement's own (diagnose's refits); true: FitInfo::likelihood and the
  /// standard errors from the likelihood's covariance.
  bool record_fit_info = true;
  /// Phases "likelihood starts" (the other moment fits and the brief fits from every start),
  /// "likelihood input" (the brief fits under zoh and band_limited) and "likelihood fit" (the full
  /// refinement: its steps are its fits and bias-correction data sets; length not known in advance).
  ProgressCallback progress;
};

struct Refinement {
  likelihood::SamplingAdequacy adequacy;
  std::optional<likelihood::Result> result;  ///< set when the likelihood was used
  std::string input_reason;  ///< why the input interpolation (set when `input: "auto"` chose it)
  /// Why the likelihood failed when its filter diverged (identify_fit then keeps the moment fit).
  std::string failure;
  /// What the user should check ("harmonic_forcing.omega moved from 1.205 in the moment fit to
  /// 49.8": another local maximum of the likelihood is likelier than a forcing 40× faster).
  std::vector<std::string> warnings;
  /// The starts the likelihood was fitted from briefly (empty: one start, the given moment fit).
  std::vector<LikelihoodStart> starts;
  std::size_t chosen_candidate = 0;  ///< 0: the given moment fit; k: the k-th of the other candidates
};

/// A warning when the likelihood moved harmonic_forcing's ω outside [0.8, 1.25]× the moment
/// fit's (an outside tester's per-record forcing with an electrical state went from ω 1.205 to
/// 49.8, 263 nats below the fit with the forcing alone, with no warning); else none.
std::vector<std::string> forcing_frequency_warnings(const Model& moment_fit, const Model& refined);

/// The moment fit of a data set (identify with the config's options), for per-record starts.
using MomentFit = std::function<Model(const Dataset&)>;

/// Refines `model` (identify's moment fit of `data`) when the settings ask for it or the
/// sampling cannot be vouched for; on success `model` becomes the refined model with
/// model.fit->likelihood and model.fit->input set. With per_record_phase, the start's phases,
/// amplitude and omega come from `moment_fit` of every record on its own (the shared-phase fit
/// of records started at unrelated times averages the forcing away): phases per record, the
/// median amplitude and omega. Throws vehs::Error (one line) for a filter that diverges, an
/// input the data cannot support, or invalid options.
///
/// With `others` (and without per_record_phase) the likelihood has several starts: the given
/// moment fit and the other moment fits `others` returns (called only when the likelihood runs),
/// fitted briefly (vehs/fit/likelihood_starts.hpp); the full refinement runs from the highest log L,
/// `model` is that start's moment fit before it is refined, and Refinement::starts lists them all.
Refinement refine_moment_fit(Model& model, const Dataset& data, const LikelihoodSettings& settings,
                             const MomentFit& moment_fit = {}, const MomentCandidates& others = {});

/// Checks that `data` can carry `how`: an interpolated input needs an input column and records
/// long enough for its stencil (cubic 4, band_limited 16 samples). Throws a one-line vehs::Error
/// prefixed with `where`.
void check_input_interpolation(InputInterpolation how, const Dataset& data, bool model_has_drive,
                               const std::string& where);

}  // namespace vehs
