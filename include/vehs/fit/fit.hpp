#pragma once
// vehs::fit — the one fit of an SDE model to measured records that identify-vehs, vehs.identify
// and diagnose's refits call (issue 33): data checks, identify's moment fit (libraries, effects,
// estimator, sparse selection, standard errors), the data's input column taken into the drift
// library, the sampling adequacy, the likelihood's refinement from every moment fit the data admit
// (the highest log L kept) with its selection, and standard errors from one covariance. In the
// manner of Ceres' Solver: options with IsValid, a summary with BriefReport.
//
//   vehs::FitOptions options;                  // the defaults fit real rigs
//   options.moment.effects = {vehs::Effect{vehs::EffectId::CoulombFriction, {}, {}}};
//   const vehs::FitSummary s = vehs::fit(data, options);
//   std::cout << s.BriefReport() << "\n";      // s.model(): the fitted model
#include <functional>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/fit/data_checks.hpp"
#include "vehs/fit/recorded_input.hpp"
#include "vehs/fit/refinement.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs {

struct FitOptions {
  /// The data checks; `check_data` before fit() applies them once (the executables do so when they
  /// read the data, where a Drop rule is reported).
  DataChecks checks;
  bool run_checks = true;
  /// identify's moment fit: libraries, effects, estimator, sparsity, criterion, folds, ...
  identify::Options moment;
  /// Which of moment's settings were chosen by the user; the others are defaults that the fit
  /// adapts to the data: driven data's libraries (vehs/fit/recorded_input.hpp), fewer folds on
  /// small data (at least 100 samples per fold).
  LibrariesGiven libraries_given;
  bool folds_given = false;
  std::string input_column = "u";  ///< the data's input column, as messages name it
  /// The likelihood's refinement: when, its options, its start.
  LikelihoodSettings likelihood;
  /// Under estimator auto, the likelihood starts from every moment fit (uli, noisy, forward) and
  /// keeps the highest (vehs/fit/likelihood_starts.hpp); false: from the chosen moment fit only.
  bool likelihood_starts = true;
  /// identify's streaming passes ("identify"), then the likelihood's phases (LikelihoodSettings::progress)
  ProgressCallback progress;
  std::function<void(const std::string&)> log;         ///< one line per step (empty: none)

  /// true when valid; else false with a one-line reason in `why` (when given).
  bool IsValid(std::string* why = nullptr) const;
};

struct FitSummary {
  identify::Result result;     ///< the fitted model (refined when the likelihood ran) and identify's report
  Refinement refinement;       ///< whether the likelihood refined it, why, its starts, warnings
  RecordedInput input;         ///< what was done with the data's input column
  std::vector<std::string> dropped;  ///< what the data checks' Drop rules removed
  double seconds = 0.0;        ///< wall time of fit()

  const Model& model() const { return result.model; }
  /// One line per step: the data, the moment fit, the likelihood (used or why not, its starts,
  /// convergence), warnings.
  std::string BriefReport() const;
  /// The lines of BriefReport that a user must read (a fit not converged, a failed likelihood,
  /// an input left out, a moved forcing frequency): empty when there is nothing to warn of.
  std::vector<std::string> Warnings() const;
};

/// The folds of identify's cross-validation for `samples` samples: the given ones, or by default
/// (under the BIC criterion, where they only feed the CV figures) fewer on small data.
int fit_folds(const FitOptions& options, std::size_t samples);

/// Why those folds cannot be used ("= 12 leaves fewer than 100 samples per fold ..."), else "".
std::string folds_problem(const FitOptions& options, std::size_t samples);

/// Fits `data` under `options` (see the header comment). Throws a one-line vehs::Error for
/// invalid options, data that fail a check under an Error rule, or data the moment fit cannot
/// read; a likelihood whose filter diverges leaves the moment fit standing, with the reason in
/// refinement.failure.
FitSummary fit(const Dataset& data, const FitOptions& options);

}  // namespace vehs
