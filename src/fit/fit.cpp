#include "vehs/fit/fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/likelihood/adequacy.hpp"
#include "vehs/likelihood/filter_diverged.hpp"

namespace vehs {

bool FitOptions::IsValid(std::string* why) const {
  std::string reason = moment.invalid_reason();
  if (reason.empty()) likelihood.options.IsValid(&reason);
  if (why) *why = reason;
  return reason.empty();
}

int fit_folds(const FitOptions& options, std::size_t samples) {
  const int folds = options.moment.folds;
  // the default folds only feed the CV figures under the BIC criterion: fewer on small data
  if (options.folds_given || options.moment.criterion != identify::Criterion::Bic) return folds;
  return static_cast<int>(std::clamp<std::size_t>(samples / 100, 2, static_cast<std::size_t>(folds)));
}

std::string folds_problem(const FitOptions& options, std::size_t samples) {
  const int folds = fit_folds(options, samples);
  if (static_cast<std::size_t>(folds) * 100 <= samples) return "";
  return "= " + std::to_string(folds) + " leaves fewer than 100 samples per fold (the data have " +
         std::to_string(samples) + ")";
}

namespace {

/// The effects' parameters of the model the likelihood refined (the moment fit's are left in
/// `dynamic_fit` and `selection` only): a model file with two values of one parameter, μ 0.0405
/// under effect_params beside sign(y) −0.0519 in the drift, misled an outside tester.
void refresh_effect_params(identify::Result& r, const identify::Options& o) {
  std::vector<Effect> term_like;
  for (const Effect& e : o.effects)
    if (effect_spec(e.id).term_like) term_like.push_back(e);
  std::vector<Effect> params = identify::effect_parameters(r.model, term_like);
  for (const Effect& e : r.model.effects) params.push_back(e);
  r.report.effect_params = std::move(params);
  r.report.user_effect_params.clear();
  for (const UserEffect& u : o.user_effects) r.report.user_effect_params.push_back(user_effect_fit(r.model, u));
}

/// The moment fits of the estimators other than `chosen` (uli, noisy, forward), kept in `results`
/// (aligned with the candidates) for the one the likelihood may start from.
std::vector<MomentCandidate> other_moment_fits(const Dataset& data, const identify::Options& o, Estimator chosen,
                                               std::vector<std::optional<identify::Result>>& results) {
  std::vector<MomentCandidate> out;
  for (Estimator e : {Estimator::Uli, Estimator::Noisy, Estimator::Forward}) {
    if (e == chosen) continue;
    identify::Options a = o;
    a.estimator = e;
    MomentCandidate c{enum_to_string(kEstimatorNames, e), std::nullopt, {}};
    try {
      results.emplace_back(identify::identify(data, a));
      c.model = results.back()->model;
    } catch (const Error& err) {
      results.emplace_back(std::nullopt);
      c.failure = err.what();
    }
    out.push_back(std::move(c));
  }
  return out;
}

/// The moment fit stands when the likelihood's filter diverged: no evidence against the model.
Refinement moment_fit_stands(const Model& model, const Dataset& data, const std::string& why,
                             const FitOptions& options) {
  Refinement r;
  r.adequacy = likelihood::assess_sampling(model, data);
  r.failure = why;
  r.warnings.push_back("the likelihood could not refine the moment fit (" + why +
                       "); the model is the moment fit, with its standard errors");
  if (options.log) options.log("likelihood: failed, the moment fit stands: " + why);
  return r;
}

/// A user's expression must be finite wherever the data go: "log(y)" on a record that crosses
/// y = 0 was refused as "ill-conditioned ... condition number infinite", which named no row.
/// Checked at every sample's (x, central-difference y, u); the error names the term and the line.
/// Once per vehs::fit (the tools' fits and diagnose's confirming refits), not in every identify
/// call of a diagnosis's draws and suspects.
void check_user_terms_finite(const Dataset& data, const identify::Options& o) {
  std::vector<std::pair<Term, bool>> terms;  // (term, in the diffusion)
  for (const Term& t : o.drift_library) terms.emplace_back(t, false);
  for (const Term& t : o.diffusion_library) terms.emplace_back(t, true);
  for (const UserEffect& u : o.user_effects)
    for (const UserEffectParam& p : u.params) terms.emplace_back(p.term, p.diffusion);
  using detail::format_number;
  for (std::size_t j = 0; j < terms.size(); ++j) {
    const auto& [t, diffusion] = terms[j];
    // (a user effect's term may also stand in a library: one pass over the data per term)
    const auto first = std::find_if(terms.begin(), terms.end(), [&](const auto& e) { return e.first == t; });
    if (!t.is_user() || first != terms.begin() + std::ptrdiff_t(j)) continue;
    for (const Record& r : data.records) {
      const double* x = data.x_of(r);
      const double* u = data.u_of(r);
      for (std::size_t i = 1; i + 1 < r.size; ++i) {
        const double y = (x[i + 1] - x[i - 1]) / (2.0 * r.dt), ui = u ? u[i] : 0.0;
        if (std::isfinite(t.value(x[i], y, ui))) continue;
        throw Error(r.source + ": line " + std::to_string(r.first_line + i) + ": the " +
                    (diffusion ? "diffusion" : "drift") + " term '" + t.name() +
                    "' is not finite at x = " + format_number(x[i], 6) + ", y = " + format_number(y, 6) +
                    (u ? ", u = " + format_number(ui, 6) : std::string()) +
                    " (y by central differences): an expression must be finite wherever the data go");
      }
    }
  }
}

/// identify's moment fit under the options the data decided (libraries, folds).
identify::Options moment_options(const Dataset& data, const FitOptions& options, RecordedInput& input) {
  identify::Options o = options.moment;
  o.progress = options.progress;
  input = use_recorded_input(data, options.input_column, options.libraries_given, o);
  if (options.log && input.added) options.log("identify: " + input.why);
  if (const std::string why = folds_problem(options, data.total_samples()); !why.empty()) throw Error("folds " + why);
  o.folds = fit_folds(options, data.total_samples());
  return o;
}

void refine(FitSummary& s, const Dataset& data, const FitOptions& options, const identify::Options& o) {
  LikelihoodSettings lik = options.likelihood;
  lik.options.log = options.log;
  lik.progress = options.progress;
  if (lik.options.select) lik.options.candidate_drift = o.drift_library, lik.options.candidate_diffusion = o.diffusion_library;
  const EffectTerms kept = identify::kept_terms(o);  // the requested effects' terms stay, as in identify's selection
  for (const TermCoef& tc : kept.drift) lik.options.keep_drift.push_back(tc.term);
  for (const TermCoef& tc : kept.diffusion) lik.options.keep_diffusion.push_back(tc.term);
  identify::Options quiet = o;
  quiet.progress = {};
  std::vector<std::optional<identify::Result>> others;  // the likelihood starts from every moment fit
  MomentCandidates other_fits;
  if (o.estimator == Estimator::Auto && options.likelihood_starts)
    other_fits = [&] { return other_moment_fits(data, quiet, s.result.model.fit->estimator, others); };
  try {
    s.refinement = refine_moment_fit(s.result.model, data, lik,
                                     [&](const Dataset& one) { return identify::identify(one, quiet).model; }, other_fits);
  } catch (const likelihood::FilterDiverged& e) {
    s.refinement = moment_fit_stands(s.result.model, data, e.what(), options);
    return;
  }
  if (const std::size_t k = s.refinement.chosen_candidate; k > 0) {
    identify::Result chosen = std::move(*others[k - 1]);
    chosen.model = std::move(s.result.model);  // the refined model
    chosen.report.estimator.reason = "the likelihood's highest start (estimator.likelihood_starts); auto had read: " +
                                     s.result.report.estimator.reason;
    chosen.report.estimator.requested = Estimator::Auto;
    s.result = std::move(chosen);
  }
  if (s.refinement.result) refresh_effect_params(s.result, o);
}

}  // namespace

FitSummary fit(const Dataset& given, const FitOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (std::string why; !options.IsValid(&why)) throw Error(why);
  std::optional<CheckedData> checked;
  if (options.run_checks) checked = check_data(given, options.checks);
  const Dataset& data = checked ? checked->data : given;
  FitSummary s;
  if (checked) s.dropped = std::move(checked->dropped);
  const identify::Options o = moment_options(data, options, s.input);
  check_user_terms_finite(data, o);
  s.result = identify::identify(data, o);
  refine(s, data, options, o);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace vehs
