#include "tools/likelihood_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/standard_errors.hpp"
#include "vehs/likelihood/input_reading.hpp"
#include "vehs/likelihood/record_phase_start.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::tools {

const char* const kLikelihoodHelp =
    "Refinement of the moment fit by maximum likelihood (exact at the data's sampling: a "
    "continuous-discrete Gaussian filter over the model's state, Ceres BFGS with automatic "
    "derivatives; vehs/likelihood/refine.hpp). Used when estimator is \"likelihood\", when this "
    "block is given, and with estimator \"auto\" whenever the sampling cannot vouch for the "
    "moment estimators (omega*dt >= 0.2 with a bias (omega*dt)^2/12 above the best relative "
    "standard error, or a recorded input with omega*dt >= 0.1; omega from the lag-1 and lag-2 "
    "increments of x, insensitive to sensor noise; see vehs/likelihood/adequacy.hpp). Keys: "
    "use (\"auto\", \"always\", \"never\"; default \"always\" when the block is given), input "
    "(how the recorded input is applied between samples: \"zoh\", \"linear\", \"cubic\", "
    "\"band_limited\", or \"auto\" (default): band_limited when less than 10 % of the input's power lies "
    "above 3/4 of the Nyquist frequency (a smooth signal that was sampled, e.g. a measured base "
    "acceleration), else zoh (a sequence held by a DAC); carried in the model file and used by "
    "simulate-vehs, its validation and diagnose-vehs), "
    "select (true: forward steps by the score test over the drift and diffusion libraries, then backward elimination, by the criterion), "
    "criterion (\"bic\" or \"lr\": likelihood-ratio test at level lr_alpha, default 1e-3), "
    "covariance (standard errors: \"observed\" information, \"fisher\", \"sandwich\"), "
    "measurement_noise (true: estimate white sensor noise on x), per_record_phase (true: one "
    "harmonic_forcing phase per record, amplitude and omega shared; records started at unrelated "
    "times), substeps (RK4 substeps per interval, 0: automatic), max_rounds, bias_correction (B > 0: "
    "remove the Gaussian filter's own bias by B data sets simulated at the estimate, standard errors "
    "x sqrt(1 + 1/B); at B = 8 +25 % CPU on the paper's model, 3.6x on Silverbox, whose interpolated "
    "input is simulated at 96 steps per interval; 0: off; default \"auto\": B = 8 when the fit estimates "
    "sensor noise and resolves it (above 2 SE), where the filter over-estimates a multiplicative noise by about 5 %, else 0, and "
    "skipped with the reason when the estimate cannot be simulated), bias_correction_seed (seed of "
    "the first simulated data set, default 1). The model file then holds \"likelihood\": "
    "measurement_sd, record_phases, log_likelihood, bic, observations, the parameters with their "
    "covariance matrix, bias_correction (datasets, seed, max_shift_se, or why it was skipped), and "
    "estimator.input.";

namespace {

LikelihoodUse use_from_string(const Config& c, const std::string& key, const std::string& s) {
  if (s == "auto") return LikelihoodUse::Auto;
  if (s == "always") return LikelihoodUse::Always;
  if (s == "never") return LikelihoodUse::Never;
  c.fail(key, "must be \"auto\", \"always\" or \"never\" (got \"" + s + "\")");
}

void set_auto_bias_correction(likelihood::RefineOptions& o) {
  o.bias_correction_datasets = kAutoBiasCorrectionDatasets;
  o.bias_correction_auto = true;
}

}  // namespace

std::string moment_estimator_name(const Config& c) {
  const std::string e = c.string_or("estimator", "auto");
  return e == "likelihood" ? "auto" : e;
}

LikelihoodSettings likelihood_settings(const Config& c) {
  LikelihoodSettings s;
  const std::string estimator = c.string_or("estimator", "auto");
  s.use = estimator == "likelihood" ? LikelihoodUse::Always
          : estimator == "auto"     ? LikelihoodUse::Auto
                                    : LikelihoodUse::Never;
  auto& o = s.options;
  o.select = true;
  o.covariance = likelihood::Covariance::Observed;
  set_auto_bias_correction(o);
  if (!c.has("likelihood")) return s;
  const Config l = c.object("likelihood", {"use", "input", "select", "criterion", "lr_alpha", "covariance",
                                           "measurement_noise", "per_record_phase", "substeps", "max_rounds",
                                           "bias_correction", "bias_correction_seed"});
  s.use = use_from_string(l, "use", l.string_or("use", "always"));
  if (estimator == "likelihood" && s.use != LikelihoodUse::Always)
    l.fail("use", "contradicts estimator \"likelihood\"");
  const std::string input = l.string_or("input", "auto");
  s.input_auto = input == "auto";
  if (!s.input_auto) o.filter.input = enum_from_string(kInputInterpolationNames, input, l.where("input"));
  o.select = l.boolean_or("select", true);
  o.criterion = enum_from_string(likelihood::kSelectionCriterionNames, l.string_or("criterion", "bic"),
                                 l.where("criterion"));
  o.lr_alpha = l.number_or("lr_alpha", 1e-3);
  o.covariance = enum_from_string(likelihood::kCovarianceNames, l.string_or("covariance", "observed"),
                                  l.where("covariance"));
  o.estimate_measurement_noise = l.boolean_or("measurement_noise", true);
  o.per_record_phase = l.boolean_or("per_record_phase", false);
  const long long sub = l.integer_at_least("substeps", 0, 0);
  if (sub > 1000) l.fail("substeps", "must be <= 1000");
  o.filter.substeps = static_cast<int>(sub);
  o.max_rounds = l.int_at_least("max_rounds", 1, 20);
  if (l.has("bias_correction") && !(l.raw("bias_correction").is_string() && l.string("bias_correction") == "auto")) {
    if (l.raw("bias_correction").is_string())
      l.fail("bias_correction", "must be \"auto\" or an integer B in [0, 1000] (got \"" + l.string("bias_correction") + "\")");
    const long long bias_sets = l.integer_at_least("bias_correction", 0, 0);
    if (bias_sets > 1000) l.fail("bias_correction", "must be <= 1000");
    o.bias_correction_datasets = static_cast<int>(bias_sets);
    o.bias_correction_auto = false;
  }
  o.bias_correction_seed = static_cast<std::uint64_t>(l.integer_at_least("bias_correction_seed", 0, 1));
  std::string why;
  if (!o.IsValid(&why)) throw Error(c.where("likelihood") + ": " + why);
  return s;
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
likelihood::ObservedModel choose_start(Model& model, const Dataset& data, const likelihood::RefineOptions& o,
                                       const MomentCandidates& others, Refinement& out) {
  likelihood::ObservedModel start{model, model.fit ? model.fit->sampling.sensor_noise_sd : 0.0, {}};
  if (!others) return start;
  std::vector<MomentCandidate> candidates{{model.fit ? enum_to_string(kEstimatorNames, model.fit->estimator) : "given", model, {}}};
  for (MomentCandidate& c : others()) candidates.push_back(std::move(c));
  out.starts = likelihood_starts(candidates, o.estimate_measurement_noise);
  if (std::count_if(out.starts.begin(), out.starts.end(), [](const LikelihoodStart& s) { return s.status.empty(); }) < 2) {
    out.starts.clear();  // one start: the single refinement below
    return start;
  }
  std::optional<likelihood::ObservedModel> best = best_start(out.starts, candidates, data, o);
  if (!best) return start;  // every brief fit failed: the refinement from the given fit says why
  for (const LikelihoodStart& s : out.starts)
    if (s.status == "chosen") out.chosen_candidate = s.candidate;
  model = *candidates[out.chosen_candidate].model;
  return *best;
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
  likelihood::ObservedModel start = choose_start(model, data, o, o.per_record_phase ? MomentCandidates{} : others, out);
  if (o.per_record_phase) likelihood::start_record_phases(start, data, moment_fit, o.filter);
  out.result = likelihood::refine(start, data, o);
  const likelihood::Result& r = *out.result;
  FitInfo fit = model.fit ? *model.fit : FitInfo{};
  fit.input = o.filter.input;
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

}  // namespace vehs::tools
