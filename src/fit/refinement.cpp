#include "vehs/fit/refinement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/standard_errors.hpp"
#include "vehs/likelihood/input_reading.hpp"
#include "vehs/likelihood/record_phase_start.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs {

LikelihoodSettings::LikelihoodSettings() {
  options.select = true;
  options.covariance = likelihood::Covariance::Observed;
  options.bias_correction_datasets = kAutoBiasCorrectionDatasets;
  options.bias_correction_auto = true;
}

void check_input_interpolation(InputInterpolation how, const Dataset& data, bool model_has_drive,
                               const std::string& where) {
  if (how == InputInterpolation::ZeroOrderHold) return;
  const std::string name = enum_to_string(kInputInterpolationNames, how);
  if (!model_has_drive)
    throw Error(where + ": input \"" + name + "\" needs a model with a drive term 'u'");
  if (!data.has_u()) throw Error(where + ": input \"" + name + "\" needs data with an input column");
  const std::size_t need = how == InputInterpolation::BandLimited ? 16 : how == InputInterpolation::Cubic ? 4 : 2;
  for (const auto& r : data.records)
    if (r.size < need)
      throw Error(where + ": input \"" + name + "\" needs records of at least " + std::to_string(need) +
                  " samples; record " + std::to_string(r.id) + " of " + r.source + " has " + std::to_string(r.size));
}

namespace {

/// The start of the full refinement: the best of the brief fits from `model` and `others` (when
/// there are other moment fits to start from; `model` becomes the chosen moment fit and
/// out.chosen_candidate its index), else `model` itself.
likelihood::ObservedModel choose_start(Model& model, const Dataset& data, const LikelihoodSettings& settings,
                                       const likelihood::RefineOptions& o, const MomentCandidates& others,
                                       Refinement& out) {
  const double noise = std::isnan(settings.start_measurement_sd)
                           ? (model.fit ? model.fit->sampling.sensor_noise_sd : 0.0)
                           : settings.start_measurement_sd;
  likelihood::ObservedModel start{model, noise, settings.start_record_phases};
  if (!others) return start;
  vehs::detail::ProgressCounter phase(settings.progress, "likelihood starts", 0, true);
  std::vector<MomentCandidate> candidates{{model.fit ? enum_to_string(kEstimatorNames, model.fit->estimator) : "given", model, {}}};
  for (MomentCandidate& c : others()) candidates.push_back(std::move(c)), phase.advance();
  out.starts = likelihood_starts(candidates, o.estimate_measurement_noise);
  if (std::count_if(out.starts.begin(), out.starts.end(), [](const LikelihoodStart& s) { return s.status.empty(); }) < 2) {
    out.starts.clear();  // one start: the single refinement below
    return start;
  }
  std::optional<likelihood::ObservedModel> best = best_start(out.starts, candidates, data, o, [&] { phase.advance(); });
  if (!best) return start;  // every brief fit failed: the refinement from the given fit says why
  for (const LikelihoodStart& s : out.starts)
    if (s.status == "chosen") out.chosen_candidate = s.candidate;
  model = *candidates[out.chosen_candidate].model;
  return *best;
}

/// Under input "auto": the spectrum cannot tell a DAC's held sequence of a smooth signal from a
/// smooth signal that was sampled (an AR(1) input held by a DAC read as band-limited put β, k₁ and
/// the input's gain 7–11 SE off, 491 nats below zoh), the likelihood can: the start is fitted
/// briefly under zoh and under band-limited interpolation and the higher log L decides.
void choose_input(const likelihood::ObservedModel& start, const Dataset& data, likelihood::RefineOptions& o,
                  Refinement& out, const ProgressCallback& progress) {
  const bool long_records = std::all_of(data.records.begin(), data.records.end(), [](const Record& r) { return r.size >= 16; });
  if (!long_records) return;  // band-limited interpolation needs 16 samples: the spectrum's reading stands
  vehs::detail::ProgressCounter phase(progress, "likelihood input", 2);
  const Dataset on = brief_share(data);
  likelihood::RefineOptions brief = brief_options(o);
  std::string results;
  double best = -std::numeric_limits<double>::infinity();
  InputInterpolation chosen = o.filter.input;
  for (InputInterpolation how : {InputInterpolation::ZeroOrderHold, InputInterpolation::BandLimited}) {
    brief.filter.input = how;
    const std::string name = enum_to_string(kInputInterpolationNames, how);
    try {
      const double logl = likelihood::refine(start, on, brief).log_likelihood;
      results += (results.empty() ? "" : ", ") + name + " " + vehs::detail::format_number(logl, 10);
      if (logl > best) best = logl, chosen = how;
    } catch (const Error& e) {
      results += (results.empty() ? "" : ", ") + name + " failed (" + e.what() + ")";
    }
    phase.advance();
  }
  phase.finish();
  if (!std::isfinite(best)) return;
  const std::string spectrum = out.input_reason;
  out.input_reason = enum_to_string(kInputInterpolationNames, chosen) + " by the likelihood (log L of a brief fit: " +
                     results + "); the spectrum read: " + spectrum;
  o.filter.input = chosen;
  if (o.log) o.log("likelihood: input " + out.input_reason);
}

/// The full refinement as the phase "likelihood fit": one step per fit (warm starts and selection
/// refits included) and per data set of the bias correction, the heartbeat in between.
likelihood::Result refine_counted(likelihood::ObservedModel& start, const Dataset& data, likelihood::RefineOptions o,
                                  const MomentFit& moment_fit, const ProgressCallback& progress) {
  vehs::detail::ProgressCounter phase(progress, "likelihood fit", 0, true);
  if (o.per_record_phase && start.record_phases.empty()) likelihood::start_record_phases(start, data, moment_fit, o.filter);
  if (progress) o.step = [&phase] { phase.advance(); };
  likelihood::Result r = likelihood::refine(start, data, o);
  phase.finish();
  return r;
}

}  // namespace

Refinement refine_moment_fit(Model& model, const Dataset& data, const LikelihoodSettings& settings,
                             const MomentFit& moment_fit, const MomentCandidates& others) {
  Refinement out;
  out.adequacy = likelihood::assess_sampling(model, data);
  const bool use = settings.use == LikelihoodUse::Always ||
                   (settings.use == LikelihoodUse::Auto && !out.adequacy.vouched);
  if (!use) return out;
  likelihood::RefineOptions o = settings.options;
  if (settings.input_auto && model.uses_drive() && data.has_u()) {
    const likelihood::InputReading reading = likelihood::read_input_interpolation(data);
    o.filter.input = reading.input;
    out.input_reason = reading.reason;
    if (o.log) o.log("likelihood: input " + enum_to_string(kInputInterpolationNames, reading.input) + " (auto: " + reading.reason + ")");
  }
  check_input_interpolation(o.filter.input, data, model.uses_drive(), "likelihood.input");
  if (o.per_record_phase && !model.find_effect(EffectId::HarmonicForcing))
    throw Error("likelihood.per_record_phase: the model has no harmonic_forcing effect (list it in 'effects')");
  for (const Effect& e : settings.start_effects)  // a refit starts from the fitted model's effects
    for (Effect& own : model.effects)
      if (own.id == e.id) own.params = e.params;
  likelihood::ObservedModel start =
      choose_start(model, data, settings, o, o.per_record_phase ? MomentCandidates{} : others, out);
  if (settings.input_auto && model.uses_drive() && data.has_u()) choose_input(start, data, o, out, settings.progress);
  out.result = refine_counted(start, data, o, moment_fit, settings.progress);
  const likelihood::Result& r = *out.result;
  FitInfo fit = model.fit ? *model.fit : FitInfo{};
  fit.input = o.filter.input;
  if (!settings.record_fit_info) {
    model = r.model.model;
    model.fit = std::move(fit);
    return out;
  }
  LikelihoodFit lf;
  lf.measurement_sd = r.model.measurement_sd;
  lf.record_phases = r.model.record_phases;
  lf.log_likelihood = r.log_likelihood;
  lf.bic = r.bic;
  lf.observations = r.summary.observations;
  lf.substeps = r.summary.substeps;
  lf.selection = o.select ? enum_to_string(likelihood::kSelectionCriterionNames, o.criterion) : "none";
  lf.covariance_method = r.summary.covariance;
  lf.converged = r.summary.converged;
  lf.reason = settings.use == LikelihoodUse::Always ? "requested" : out.adequacy.reason;
  const std::size_t k = r.parameters.size();
  for (std::size_t i = 0; i < k; ++i) lf.parameters.push_back(r.parameters[i].name);
  lf.values = r.values;
  lf.covariance.resize(k * k);
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = 0; j < k; ++j) lf.covariance[i * k + j] = r.covariance(long(i), long(j));
  lf.bias_correction_datasets = r.summary.bias_correction_datasets;
  lf.bias_correction_seed = r.summary.bias_correction_seed;
  lf.bias_correction_max_shift_se = r.summary.bias_correction_max_se;
  lf.bias_correction_skipped = r.summary.bias_correction_skipped;
  fit.likelihood = std::move(lf);
  out.warnings = forcing_frequency_warnings(model, r.model.model);
  if (!r.summary.converged)  // never silent: the estimates and their errors are not at a maximum
    out.warnings.push_back("the likelihood did not converge (" + r.summary.message + ", " +
                           std::to_string(r.summary.rounds) + " rounds): its estimates are not at a maximum and "
                           "their standard errors do not hold; likelihood.max_rounds, a simpler model or the moment "
                           "fit (\"likelihood\": {\"use\": \"never\"}) may help");
  model = r.model.model;  // its covariance the block of lf.covariance over the model's parameters
  model.fit = std::move(fit);
  standard_errors_from_covariance(model, "likelihood");
  return out;
}

std::vector<std::string> forcing_frequency_warnings(const Model& moment, const Model& refined) {
  const Effect* a = moment.find_effect(EffectId::HarmonicForcing);
  const Effect* b = refined.find_effect(EffectId::HarmonicForcing);
  if (!a || !b || !a->params.count("omega") || !b->params.count("omega")) return {};
  const double w0 = a->params.at("omega"), w = b->params.at("omega");
  if (!(w0 > 0.0) || (w >= 0.8 * w0 && w <= 1.25 * w0)) return {};
  return {"the likelihood moved harmonic_forcing.omega from " + vehs::detail::format_number(w0, 4) + " (the moment fit) to " + vehs::detail::format_number(w, 4) +
          ": likely another local maximum, not the forcing; compare the log-likelihood with a fit of fewer effects "
          "(e.g. the forcing alone)"};
}

}  // namespace vehs
