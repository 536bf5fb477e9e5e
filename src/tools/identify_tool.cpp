#include "tools/identify_tool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <tuple>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <iostream>
#include <sstream>

#include "vehs/core/error.hpp"
#include "tools/data_checks.hpp"
#include "tools/identify_file.hpp"
#include "tools/likelihood_config.hpp"
#include "vehs/core/diffusion_in_data.hpp"
#include "vehs/likelihood/signals.hpp"
#include "tools/identify_figures.hpp"
#include "tools/measurement_config.hpp"
#include "tools/terminal_progress.hpp"
#include "tools/parameter_table.hpp"
#include "tools/fit_sections.hpp"
#include "tools/budget.hpp"
#include "tools/study_output.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/identify/dynamic.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/core/detail/format.hpp"

namespace vehs::tools {

using namespace vehs::identify;

namespace {

const char* const kEffectsHelp =
    "Physical effects to include (docs/model-file.md#effects): a list of names or {\"name\": ..., \"params\": "
    "{...}}. Term-like effects (asymmetric_stiffness, coulomb_friction, quadratic_damping, "
    "nonlinear_damping, velocity_dependent_noise) add their terms to the dictionaries and keep "
    "them through the sparse regression; their physical parameters (e.g. mu = -coef of sign(y)) "
    "are reported with standard errors under \"effect_params\" (given params are ignored: the "
    "fit is linear). Dynamic effects are fitted by profile least squares of the drift contrast "
    "over their nonlinear parameters, jointly with the drift terms, and written to the model's "
    "\"effects\" with standard errors (sandwich, batch means); params given in the entry are held "
    "fixed. impact_stop: force -k_stop*(x-gap) beyond gap and -k_stop*(x+gap_neg) beyond -gap_neg; "
    "gaps from a grid of quantiles of x refined by scan, golden section and joint Newton steps, "
    "k_stop linear (needs samples beyond the gaps). harmonic_forcing: amplitude*cos(omega*t + "
    "phase) with t the records' absolute time; omega from the largest lines of the Welch "
    "spectrum of the baseline residuals refined on the profile, then amplitude and phase (amplitude "
    "can be fixed only together with phase). electromechanical_coupling: force -coupling*v with "
    "dv = (y - lambda*v) dt, v filtered from x itself; lambda on a log grid from 1/(record "
    "duration) to 0.2/h; weakly identifiable against damping and stiffness (its force at one "
    "frequency mixes both), so expect larger standard errors on beta, lambda and coupling. "
    "colored_noise (OU excitation, force eta with d eta = -eta/tau dt + sqrt(intensity)/tau dW): "
    "tau and intensity from the exponential decay of the drift-residual autocovariance at lags >= "
    "2 strides, drift refitted on Kalman prediction errors (GLS; unbiased damping), white a22 "
    "from the residual variance minus the OU part; uses the uli estimator; cannot yet be combined "
    "with the other dynamic effects. Details of the fit are written under "
    "\"dynamic_fit\". A user's own effect is {\"name\": ..., \"drift\": {\"param\": \"term\", ...}, "
    "\"diffusion\": {...}}: each parameter the coefficient of its term (an expression in x, y, u), "
    "the terms kept through every selection, the parameters under \"effect_params\" with \"user\": true "
    "(docs/model-file.md#user-effects).";

std::vector<Term> parse_term_list(const Config& c, const std::string& key) {
  std::vector<Term> out;
  for (const auto& name : c.string_list(key)) {
    try {
      out.push_back(Term::parse(name));
    } catch (const Error& e) {
      c.fail(key, e.what());
    }
  }
  return out;
}

std::vector<Term> parse_library(const Config& c, const std::string& key, bool drift) {
  if (!c.has(key)) return drift ? paper_drift_library(11, 3) : paper_diffusion_library(4);
  const auto& v = c.raw(key);
  if (v.is_string() && v.get<std::string>() == "paper")
    return drift ? paper_drift_library(11, 3) : paper_diffusion_library(4);
  if (v.is_object()) {
    if (drift) {
      const Config o = c.object(key, {"K1", "K2"});
      const long long K1 = o.integer_at_least("K1", 0, 11), K2 = o.integer_at_least("K2", 0, 3);
      if (K1 > 40 || K2 > 40 || K1 + K2 == 0) c.fail(key, "needs 0 <= K1, K2 <= 40 and K1 + K2 > 0");
      return paper_drift_library(static_cast<int>(K1), static_cast<int>(K2));
    }
    const Config o = c.object(key, {"M"});
    const long long M = o.integer_at_least("M", 0, 4);
    if (M > 40) c.fail(key, "needs M <= 40");
    return paper_diffusion_library(static_cast<int>(M));
  }
  std::vector<Term> lib = parse_term_list(c, key);
  for (std::size_t i = 0; i < lib.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (lib[i] == lib[j]) c.fail(key, "lists the term '" + lib[i].name() + "' twice");
  return lib;
}


std::vector<double> number_list(const Config& c, const std::string& key) {
  const auto& v = c.raw(key);
  std::vector<double> out;
  if (v.is_number()) return {c.positive(key)};
  if (!v.is_array() || v.empty()) c.fail(key, "must be a positive number or a list of them");
  for (const auto& e : v) {
    if (!e.is_number() || !(e.get<double>() > 0.0) || !std::isfinite(e.get<double>()))
      c.fail(key, "must contain only positive numbers");
    out.push_back(e.get<double>());
  }
  return out;
}

sim::InitialCondition parse_x0(const Config& c, const std::string& key, int records) {
  sim::InitialCondition ic;
  if (!c.has(key)) return ic;
  const auto& v = c.raw(key);
  if (v.is_object()) {
    const Config o = c.object(key, {"uniform"});
    const auto& u = o.raw("uniform");
    if (!u.is_array() || u.size() != 2 || !u[0].is_number() || !u[1].is_number() ||
        !(u[0].get<double>() <= u[1].get<double>()))
      c.fail(key, "must be {\"uniform\": [a, b]} with a <= b");
    ic.lo = u[0].get<double>();
    ic.hi = u[1].get<double>();
    return ic;
  }
  if (v.is_array()) {
    if (static_cast<int>(v.size()) != records)
      c.fail(key, "needs one value per record (" + std::to_string(records) + ")");
    ic.uniform = false;
    for (const auto& e : v) {
      if (!e.is_number()) c.fail(key, "must contain numbers");
      ic.values.push_back(e.get<double>());
    }
    return ic;
  }
  c.fail(key, "must be {\"uniform\": [a, b]} or a list of one value per record");
}

Dataset sample_range(const Config& c, const Dataset& data) {
  const auto& v = c.raw("samples");
  if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer() ||
      v[0].get<long long>() < 0 || v[1].get<long long>() < v[0].get<long long>() + 16)
    c.fail("samples", "must be [first, last] with integers 0 <= first and last >= first + 16");
  if (data.records.size() != 1)
    c.fail("samples", "needs data with one record (they have " + std::to_string(data.records.size()) + ")");
  const auto first = v[0].get<std::size_t>(), last = v[1].get<std::size_t>();
  if (last > data.records[0].size)
    c.fail("samples", "ends at " + std::to_string(last) + " but the record has " + std::to_string(data.records[0].size) + " samples");
  return likelihood::slice_record(data, 0, first, last);
}

std::string g(double v, int digits = 6) { return vehs::detail::format_number(v, digits); }

std::string removal_note(const likelihood::SelectionStep& st) {
  if (st.by_wald) return " (Wald z^2, no refit)";
  return st.together > 1 ? " (with " + std::to_string(st.together - 1) + " other(s) in one refit)" : "";
}

void print_refinement(const Refinement& f) {
  std::printf("sampling: %s\n", f.adequacy.reason.c_str());
  if (!f.result) {
    if (!f.failure.empty())
      std::printf("  likelihood failed, the moment fit stands: %s\n", f.failure.c_str());
    else if (!f.adequacy.vouched)
      std::printf("  (the likelihood would refine this fit: estimator \"auto\" or \"likelihood\")\n");
    return;
  }
  const auto& r = *f.result;
  std::printf("%s\n", r.summary.BriefReport().c_str());
  for (const auto& st : r.summary.selection)
    if (!st.added.empty())
      std::printf("  selection: add    %-16s |z| %8.3g, 2 dlogL %10.4g vs %.3g: %s\n", st.added.c_str(), st.z, st.delta,
                  st.threshold, st.accepted ? "added" : "not added");
    else
      std::printf("  selection: remove %-16s |z| %8.3g, 2 dlogL %10.4g vs %.3g: %s%s\n", st.removed.c_str(), st.z,
                  st.delta, st.threshold, st.accepted ? "removed" : "kept", removal_note(st).c_str());
  std::printf("log L %s, BIC %s; measurement_sd %s\n", g(r.log_likelihood, 10).c_str(), g(r.bic, 10).c_str(),
              g(r.model.measurement_sd, 4).c_str());
}

}  // namespace

const ConfigSchema& identify_schema() {
  static const ConfigSchema schema = with_keys_after("output", measurement_keys(), ConfigSchema{
      "identify-vehs",
      "Identifies the drift b2(x, y) and diffusion a22(x) of dX = Y dt, dY = b2 dt + sqrt(a22) dB "
      "from displacement records, with a standard error for every coefficient, and writes a model "
      "file (docs/model-file.md). With a `study` object it runs a consistency study instead (the "
      "seed paper's Table 4): simulate, identify, tabulate mean (sd) per parameter.",
      {
          {"data", "path | [paths]",
           "Measurement files: CSV (t, x [, traj, u] columns; `#` comments, `,` `;` or tab "
           "delimiters), .npy (structured, or 2-D with `columns`) or .mat. Required unless `study` "
           "is given (or `measurement` names them). A path may be a glob pattern (\"run_*.csv\": the matching files in byte order, expanded by the tool, not a shell; a pattern that matches nothing is an error naming it).",
           "", true},
          {"output", "path",
           "Model file to write (JSON, atomically). In study mode: the study's JSON; a CSV table "
           "is written beside it (same name, .csv). Never written when the fitted diffusion a22 is "
           "negative at a state the data visit.",
           ""},
          {"samples", "[first, last]",
           "Use only samples [first, last) of the data (one record; applied after detrend, so "
           "that the offsets are those of the whole record), e.g. the estimation part of a "
           "benchmark split.",
           "", true},
          {"figures", "path",
           "Folder for the figure of the fit (identify_fit.svg with its CSVs and gnuplot script): the drift "
           "as a force vs x at y = 0 and vs y at x = 0, the potential and the diffusion, each with a 95 % band "
           "from the covariance of the estimates and binned Kramers-Moyal estimates from the data.",
           "", true},
          {"drift_library", "{\"K1\", \"K2\"} | [terms] | \"paper\"",
           "Drift dictionary: the paper's Eq. 11 [1, x, ..., x^(K1-1), y, x y, ..., x^(K2-1) y], "
           "or an explicit list of term names (\"x^3\", \"x^2*y\", \"y^3\", \"sign(y)\", "
           "\"y*|y|\", \"u\"). Without this key, data with an input column (columns.u, default "
           "\"u\") get driven data's default library, {\"K1\": 4, \"K2\": 3} and the drive term "
           "u (said on stderr and in the model file's data.input); a given library without u while "
           "the data have an input is warned about (the recorded input is then not used).",
           "{\"K1\": 11, \"K2\": 3}; with an input column {\"K1\": 4, \"K2\": 3} and u"},
          {"diffusion_library", "{\"M\"} | [terms] | \"paper\"",
           "Diffusion dictionary: the paper's Eq. 17 [1, x, ..., x^M], or a list of term names. "
           "Data with an input column and no drift_library: [\"1\"] by default.",
           "{\"M\": 4}; [\"1\"] with an input column"},
          {"effects", "[names | {name, params} | {name, drift, diffusion}]", kEffectsHelp, "[]"},
          {"keep_terms", "{\"drift\": [...], \"diffusion\": [...]}",
           "Terms the sparse regression must never remove.", "{}"},
          {"estimator", "string",
           "auto (measure how the data were sampled and choose), paper (the seed paper's method, "
           "for comparison: forward differences, raw Kramers-Moyal diffusion), forward (forward "
           "differences + diffusion from drift residuals: data from an explicit scheme at the "
           "recorded step), uli (underdamped Langevin inference with Ito correction: a sensor "
           "sampling a continuous process), noisy (ULI on a stride, tolerating white sensor "
           "noise on x), likelihood (the auto moment fit refined by maximum likelihood; see "
           "`likelihood`). With auto the likelihood refines the moment fit whenever the sampling "
           "cannot vouch for the expansions; values on a grid whose rounding makes >= 1 % of the "
           "acceleration's variance (ADC counts) are never read as an explicit scheme's.",
           "\"auto\""},
          {"likelihood", "object", kLikelihoodHelp, "", true},
          {"stride", "integer",
           "ULI stride k (uli, noisy): finite differences over k samples. 0 chooses: 1 for uli, "
           "from the measured sensor-noise level for noisy.",
           "0"},
          {"discretization_correction", "boolean",
           "uli, noisy: remove the O(h^2) error (h^2/12) x'''' of the central second difference "
           "from the acceleration target (x'''' from a pilot drift fit).",
           "true"},
          {"sparsity", "string", "ssr (stepwise sparse regression), stlsq (thresholding), none.", "\"ssr\""},
          {"ssr_rule", "string",
           "Term SSR removes at each step: t_ratio (smallest |coef|/stderr, scale-free) or "
           "abs_coef (smallest |coef|, as in the paper). Default: t_ratio (abs_coef for "
           "estimator paper).",
           "", true},
          {"criterion", "string",
           "How the SSR step is chosen: bic (n log(L/n)/phi + p log n with phi the measured "
           "long-run variance factor of the residuals: consistent selection), cv_1se (blocked "
           "cross-validation over contiguous time, one-standard-error rule), cv_min. CV figures "
           "and BIC of every step are written either way.",
           "\"bic\""},
          {"folds", "integer", "Cross-validation folds: contiguous time blocks of every record (at most 1000 and at "
           "most one per 100 samples of the data).", "10"},
          {"stlsq_threshold", "number", "STLSQ: |coef| threshold on the coefficients of the data scaled to O(1) by powers of ten (see units).", "0.05"},
          {"se_block", "integer",
           "Rows per batch of the batch-means covariance behind the standard errors: 0 (automatic: the longer "
           "of 1024 rows and 50x the residual correlation range, shortened on short data to keep about 30 "
           "batches per estimated parameter, never below 256) or 256 to the fitted rows / max(30, folds). "
           "Rounded to a multiple of 256; a batch ends at a fold or record boundary. The model file's "
           "fit.stderr_method states the batches used.",
           "0"},
          {"pilot_samples", "integer",
           "Rows of the pilot fits that diagnose the sampling and set the diffusion weights.",
           "250000"},
          {"noise_share_target", "number",
           "noisy: share of sensor noise in the variance of the acceleration estimate that the "
           "automatic stride aims at (higher: smaller stride, less discretisation bias, more "
           "variance).",
           "0.95"},
          {"study", "object",
           "Consistency study instead of identification: {\"truth\": model or path, \"dt\": "
           "number or list, \"samples\": number or list (per record; the grid is dt x samples), "
           "\"repeats\": 10, \"records\": 10, \"scheme\": \"rk4_euler\", \"substeps\": 1, "
           "\"x0\": {\"uniform\": [-1.5, 1.5]}, \"seed\": 1, \"sensor_noise\": 0, \"burn_in\": "
           "0}. Prints the paper's Table 4 layout, writes JSON and CSV, and reports the coverage "
           "of the nominal 95 % intervals.",
           "", true},
          force_key(),
      },
      "Outputs: the model file holds drift, diffusion, stderr, covariance (of the estimates: "
      "parameter names and matrix) and the extra keys units, estimator, sampling (how the data "
      "were sampled), residuals, selection (the whole sparse-regression path with BIC and CV "
      "figures), fit, data (with the reading summary: gaps, missing runs, time jitter) and "
      "provenance. A standard error that cannot be computed is an error naming the parameter.\n"
      "Examples: identify-vehs data/paper/identify.json (the paper's data, default settings); "
      "identify-vehs data/identify/table4.json (the paper's Table 4 as a study); "
      "identify-vehs data/own_data/identify.json (a logger's CSV in mm and s)."});
  return schema;
}

identify::Options identify_options(const Config& c) {
  Options o;
  o.drift_library = parse_library(c, "drift_library", true);
  o.diffusion_library = parse_library(c, "diffusion_library", false);
  if (c.has("effects")) {
    const auto& ef = c.raw("effects");
    if (!ef.is_array()) c.fail("effects", "must be a list of effect names or {name, params}");
    for (std::size_t i = 0; i < ef.size(); ++i) {
      const std::string where = c.where("effects") + "[" + std::to_string(i) + "]";
      if (is_user_effect_json(ef[i])) {
        o.user_effects.push_back(user_effect_from_json(ef[i], where));
        continue;
      }
      const Effect e = effect_from_json(ef[i], where, false);
      if (e.id == EffectId::HarmonicForcing && e.params.count("amplitude") && !e.params.count("phase"))
        throw Error(where + ".params.amplitude: harmonic_forcing's amplitude can only be held fixed together with phase");
      if (e.id == EffectId::ColoredNoise)
        for (const auto& prev : o.effects)
          if (is_dynamic(prev.id) && prev.id != e.id)
            throw Error(where + ": colored_noise cannot yet be combined with the dynamic effect '" + prev.name() + "'");
      if (is_dynamic(e.id) && e.id != EffectId::ColoredNoise)
        for (const auto& prev : o.effects)
          if (prev.id == EffectId::ColoredNoise)
            throw Error(where + ": colored_noise cannot yet be combined with the dynamic effect '" + e.name() + "'");
      for (const auto& prev : o.effects)
        if (prev.id == e.id) throw Error(where + ": effect '" + e.name() + "' is listed twice");
      o.effects.push_back(e);
    }
  }
  if (c.has("keep_terms")) {
    const Config k = c.object("keep_terms", {"drift", "diffusion"});
    if (k.has("drift")) o.keep_drift = parse_term_list(k, "drift");
    if (k.has("diffusion")) o.keep_diffusion = parse_term_list(k, "diffusion");
    // a kept term outside its dictionary would be silently ignored
    for (const auto& [list, library, name] : {std::tuple(&o.keep_drift, &o.drift_library, "drift"),
                                              std::tuple(&o.keep_diffusion, &o.diffusion_library, "diffusion")})
      for (const Term& t : *list)
        if (std::find(library->begin(), library->end(), t) == library->end())
          k.fail(name, "keeps '" + t.name() + "', which is not in the " + name + " dictionary ('" + name +
                           "_library')");
  }
  o.estimator = enum_from_string(kEstimatorNames, moment_estimator_name(c), c.where("estimator"));
  o.stride = c.int_at_least("stride", 0, 0);
  o.discretization_correction = c.boolean_or("discretization_correction", true);
  o.sparsity = enum_from_string(kSparsityNames, c.string_or("sparsity", "ssr"), c.where("sparsity"));
  if (c.has("ssr_rule")) {
    o.ssr_rule = enum_from_string(kSsrRuleNames, c.string("ssr_rule"), c.where("ssr_rule"));
    o.ssr_rule_set = true;
  }
  o.criterion = enum_from_string(kCriterionNames, c.string_or("criterion", "bic"), c.where("criterion"));
  o.folds = c.int_at_least("folds", 1, 10);
  if (o.folds > 1000) c.fail("folds", "must be at most 1000 (got " + std::to_string(o.folds) + ")");
  o.stlsq_threshold = c.non_negative_or("stlsq_threshold", 0.05);
  // settings of a sparsity rule that is not used would be ignored silently
  if (c.has("stlsq_threshold") && o.sparsity != Sparsity::Stlsq)
    c.fail("stlsq_threshold", "is given but 'sparsity' is not \"stlsq\"");
  if (c.has("ssr_rule") && o.sparsity != Sparsity::Ssr) c.fail("ssr_rule", "is given but 'sparsity' is not \"ssr\"");
  o.se_block = static_cast<std::size_t>(c.integer_at_least("se_block", 0, 0));
  o.pilot_samples = static_cast<std::size_t>(c.integer_at_least("pilot_samples", 1000, 250000));
  o.noise_share_target = c.number_or("noise_share_target", 0.95);
  if (!(o.noise_share_target > 0.0 && o.noise_share_target < 1.0))
    c.fail("noise_share_target", "must be in (0, 1)");
  if (auto why = o.invalid_reason(); !why.empty()) throw Error(c.file() + ": " + why);
  return o;
}

identify::StudyOptions study_options(const Config& c) {
  if (c.has("data")) c.fail("data", "cannot be combined with 'study' (the study simulates its data)");
  if (c.has("likelihood") || c.string_or("estimator", "auto") == "likelihood")
    c.fail("study", "runs the moment estimators only (the likelihood studies are bench/likelihood.sh)");
  const Config s = c.object("study", {"truth", "dt", "samples", "repeats", "records", "scheme",
                                      "substeps", "x0", "seed", "sensor_noise", "burn_in"});
  StudyOptions o;
  o.truth = model_from_config_value(s.raw("truth"), s.where("truth")).model;
  validate_model(o.truth, s.where("truth"));
  const auto dts = number_list(s, "dt");
  const auto ns = number_list(s, "samples");
  for (double dt : dts)
    for (double n : ns) {
      if (n != std::floor(n) || n < 100) s.fail("samples", "must be integers >= 100");
      o.points.push_back({dt, static_cast<std::size_t>(n)});
    }
  o.repeats = s.int_at_least("repeats", 2, 10);
  o.records = s.int_at_least("records", 1, 10);
  o.scheme = enum_from_string(sim::kSchemeNames, s.string_or("scheme", "rk4_euler"), s.where("scheme"));
  o.substeps = s.int_at_least("substeps", 1, 1);
  o.x0 = parse_x0(s, "x0", o.records);
  o.seed = static_cast<std::uint64_t>(s.integer_at_least("seed", 0, 1));
  o.sensor_noise = s.non_negative_or("sensor_noise", 0.0);
  o.burn_in = s.non_negative_or("burn_in", 0.0);
  o.identify = identify_options(c);
  if (auto why = o.invalid_reason(); !why.empty()) throw Error(c.file() + ": study: " + why);
  return o;
}

namespace {

/// "x's mean is N standard deviations from 0: …" when the data's offset dwarfs their spread
/// (|mean| > 3 sd, all records pooled), else "".
std::string detrend_hint(const Dataset& data) {
  double m = 0.0, q = 0.0;
  for (double v : data.x) m += v, q += v * v;
  m /= double(data.x.size());
  const double sd = std::sqrt(std::max(q / double(data.x.size()) - m * m, 0.0));
  if (!(std::abs(m) > 3.0 * sd)) return "";
  return "x's mean is " + g(std::abs(m) / sd) + " standard deviations from 0: \"detrend\": \"mean\" removes each record's offset";
}

/// A variance rate cannot be negative where the data go: the fit's diffusion terms are not
/// supported by the data (vehs/core/diffusion_in_data.hpp); the model is not written.
void require_diffusion_in_data(const Model& m, const Dataset& data, const std::string& where) {
  const bool any = std::any_of(m.diffusion.begin(), m.diffusion.end(), [](const TermCoef& tc) { return tc.coef != 0.0; });
  if (!any)
    throw Error("identify: the selection kept no diffusion term (a22 = 0: no noise) — the data's increments are "
                "read as noise-free, which a model file cannot hold; look at the data (values rounded to a coarse "
                "grid, a stretch of repeated values?) or give \"sparsity\": \"none\" with diffusion_library [\"1\"]; " +
                where + " not written");
  const DiffusionInData low = lowest_diffusion_in_data(m, data, m.fit ? m.fit->stride : 1);
  if (low.negative == 0) return;
  const Record& rec = data.records[low.record];
  std::string terms;
  bool on_y = false;
  for (const auto& tc : m.diffusion) terms += (terms.empty() ? "" : ", ") + tc.term.name(), on_y = on_y || tc.term.depends_on_y();
  throw Error("identify: the fitted diffusion a22 = " + g(low.a22) + " is negative at x = " + g(low.x) +
              (on_y ? ", y = " + g(low.y) : std::string()) + " (" + record_name(rec) + ", line " +
              std::to_string(rec.first_line + low.sample) + "; " + std::to_string(low.negative) + " of " +
              std::to_string(low.samples) + " samples): the data do not support the diffusion terms " + terms +
              " (a variance rate is >= 0); a smaller diffusion_library (e.g. [\"1\"]) or a look at the data "
              "(quantised, clipped?); " + where + " not written");
}

}  // namespace

FitOptions fit_options(const Config& c) {
  FitOptions f;
  f.moment = identify_options(c);
  f.libraries_given = {c.has("drift_library"), c.has("diffusion_library")};
  f.folds_given = c.has("folds");
  f.input_column = input_column_name(c);
  f.likelihood = likelihood_settings(c);
  f.checks = data_checks(c);
  f.run_checks = false;  // applied when the data are read (load_measurements, vehs.read's records)
  return f;
}

vehs::FitSummary identify_fit(const Config& c, FitOptions f, const Dataset& loaded, const ProgressCallback& progress,
                              const std::function<void(const std::string&)>& log, std::optional<Dataset>& ranged) {
  f.progress = progress;
  f.log = log;
  if (c.has("samples")) ranged = sample_range(c, loaded);
  const Dataset& data = ranged ? *ranged : loaded;
  if (const std::string why = folds_problem(f, data.total_samples()); !why.empty()) c.fail("folds", why);
  try {
    return fit(data, f);
  } catch (const Error& e) {  // a DC offset makes 1, x, x², … collinear: say the cure
    const std::string what = e.what(), hint = detrend_hint(data);
    if (what.find("ill-conditioned") == std::string::npos || c.has("detrend") || hint.empty()) throw;
    throw Error(what + "; " + hint);
  }
}

IdentifiedInMemory identify_in_memory(const Config& c, const FitOptions& options, const Dataset& data,
                                      const ProgressCallback& progress,
                                      const std::function<void(const std::string&)>& log,
                                      std::optional<Dataset>& ranged, const std::string& where) {
  const auto start = std::chrono::steady_clock::now();
  IdentifiedInMemory out{identify_fit(c, options, data, progress, log, ranged), {}};
  validate_model(out.fit.result.model, where);
  require_diffusion_in_data(out.fit.result.model, ranged ? *ranged : data, where);
  for (const Effect& e : out.fit.result.model.effects)  // what simulate-vehs refuses to read, never written
    if (const std::string why = effect_domain_violation(e); !why.empty())
      throw Error("identify: the fit puts " + why + ": the data do not support " + e.name() +
                  " as the catalogue defines it; " + where + " not written");
  out.sections = identify_report_sections(out.fit.result);
  out.sections["estimator"]["sampling_adequacy"] = adequacy_json(out.fit.refinement);
  if (!out.fit.refinement.starts.empty())
    out.sections["estimator"]["likelihood_starts"] = likelihood_starts_json(out.fit.refinement.starts);
  if (!out.fit.input.column.empty()) out.sections["data"]["input"] = recorded_input_json(out.fit.input);
  out.sections["fit"]["in_memory_seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

namespace {

/// Operations of one regression on `rows` rows: the Gram matrix (rows x terms^2) and the
/// selection (up to `terms` eliminations of a terms^3 solve).
double regression_operations(double rows, const identify::Options& o) {
  const double terms = static_cast<double>(o.drift_library.size() + o.diffusion_library.size());
  return rows * terms * terms + terms * terms * terms * terms;
}

const char* const kLowerRegression = "use a smaller drift_library or diffusion_library, or less data";

/// Simulation steps and regression operations of a study (docs/config.md, Budgets).
std::vector<Estimate> study_estimates(const StudyOptions& so) {
  double steps = 0.0, operations = 0.0;
  for (const auto& p : so.points) {
    const double samples = static_cast<double>(p.samples);
    steps += double(so.repeats) * so.records * (samples + std::round(so.burn_in / p.dt)) * so.substeps;
    operations += double(so.repeats) * regression_operations(double(so.records) * samples, so.identify);
  }
  return {{Resource::Steps, steps, "integration steps (study: repeats x records x samples x substeps)",
           "use fewer repeats, records or samples"},
          {Resource::Steps, operations, "regression operations (study: repeats x rows x terms^2)",
           "use fewer repeats, records or samples, or a smaller library"}};
}

}  // namespace

int run_identify(Config& c, const AppOptions& app) {
  const std::string output = c.path("output");
  if (c.has("study")) {
    StudyOptions so = study_options(c);
    check_budget(c, study_estimates(so));
    so.progress = app.progress;
    const StudyResult r = run_study(so);
    nlohmann::ordered_json j = study_to_json(r);
    j["config"] = c.json();
    write_json_atomically(output, j);
    std::filesystem::path csv(output);
    csv.replace_extension(".csv");
    study_table(r).write_csv(csv.string());
    std::cout << study_text(r);
    if (!app.quiet) std::cerr << "identify-vehs: wrote " << output << " and " << csv.string() << "\n";
    return 0;
  }
  if (!c.has("data")) c.fail("data", "is missing (list the measurement files, or give 'study')");
  bool need_u = false;  // the options are checked before any file is read
  for (const auto& t : identify_options(c).drift_library) need_u = need_u || t.depends_on_u();
  (void)likelihood_settings(c);
  const nlohmann::ordered_json units = units_block(c);
  const auto files = c.path_list("data");
  // an input column is read whenever the files have one: the default library takes it in, and a
  // given library that leaves it out is warned about (vehs/fit/recorded_input.hpp)
  LoadedData loaded = load_measurements(c, need_u, app, true);
  {  // the library's size against the data's, before any fitting
    const double rows = static_cast<double>(loaded.data.total_samples());
    const identify::Options o = identify_options(c);
    const std::size_t terms = o.drift_library.size() + o.diffusion_library.size();
    check_budget(c, {{Resource::Steps, regression_operations(rows, o),
                      "regression operations (" + g(rows) + " rows x " + std::to_string(terms) + " library terms^2 + terms^4)",
                      kLowerRegression}});
  }
  const std::string& detrend = loaded.detrend;
  std::function<void(const std::string&)> log;
  if (!app.quiet) log = [](const std::string& line) { std::cerr << stderr_line_start() << line << "\n"; };
  std::optional<Dataset> ranged;
  IdentifiedInMemory identified = identify_in_memory(c, fit_options(c), loaded.data, app.progress, log, ranged, output);
  const Dataset& data = ranged ? *ranged : loaded.data;
  identify::Result& r = identified.fit.result;
  const Refinement& refinement = identified.fit.refinement;
  // data summary and provenance
  nlohmann::ordered_json ds;
  ds["files"] = files;
  ds["records"] = data.records.size();
  ds["samples"] = data.total_samples();
  ds["dt"] = r.model.fit->sampling.dt;
  double duration = 0.0, xmin = data.x.empty() ? 0.0 : data.x[0], xmax = xmin;
  for (const auto& rec : data.records) duration += static_cast<double>(rec.size - 1) * rec.dt;
  for (double v : data.x) xmin = std::min(xmin, v), xmax = std::max(xmax, v);
  ds["duration"] = duration;
  ds["x_range"] = {xmin, xmax};
  ds["detrend"] = detrend;
  ds["reading"] = read_summary_json(loaded.summary);
  nlohmann::ordered_json& sections = identified.sections;
  if (!units.empty()) sections["units"] = units;
  if (sections.contains("data")) ds.update(sections["data"]);  // identify_in_memory's input
  sections["data"] = ds;
  sections["provenance"] = {{"tool", "identify-vehs"}, {"library", library_version()}, {"config", c.json()}};
  std::string figure;
  if (c.has("figures")) {
    figure = identify_figure(c.path("figures"), r.model, data, units);
    sections["figure"] = figure;
  }
  write_model_file(output, r.model, sections);
  if (const SamplingDiagnosis& s = r.model.fit->sampling; r.report.estimator.sampling_unexplained)
    std::cerr << "warning: " << output << ": the sampling diagnosis cannot explain the data (ULI residuals' lag-k "
              << "autocorrelation " << g(s.rho_k) << " at stride " << s.stride << ", neither about 0 nor about +1/4 "
              << "at the strides tried): quantised values, dropouts, stuck or clipped stretches? the estimates may be "
              << "biased beyond their standard errors\n";
  if (const RecordedInput& in = identified.fit.input; !in.warning.empty())
    std::cerr << "warning: " << output << ": " << in.warning << "\n";
  for (const std::string& w : refinement.warnings) std::cerr << "warning: " << output << ": " << w << "\n";
  if (!app.quiet) {
    std::printf("estimator: %s (stride %d; %s)\n", enum_to_string(kEstimatorNames, r.model.fit->estimator).c_str(),
                r.model.fit->stride, r.report.estimator.reason.c_str());
    std::fputs(parameter_table(r.model, units).c_str(), stdout);
    print_refinement(refinement);
    std::printf("%zu rows in %.2f s; model written to %s\n", r.report.fit.rows, r.report.fit.seconds, output.c_str());
    if (!figure.empty()) std::printf("figure: %s\n", figure.c_str());
  }
  return 0;
}

}  // namespace vehs::tools
