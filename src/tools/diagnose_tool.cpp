#include "tools/diagnose_tool.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "tools/data_checks.hpp"
#include "tools/diagnosis_file.hpp"
#include "tools/diagnosis_report.hpp"
#include "tools/history.hpp"
#include "tools/html_report.hpp"
#include "tools/measurement_config.hpp"
#include "tools/refit_config.hpp"
#include "tools/parameter_table.hpp"
#include "vehs/core/error.hpp"
#include "vehs/io/atomic_file.hpp"
#include "vehs/io/output_transaction.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

namespace vehs::tools {

using namespace vehs::diagnose;

namespace fs = std::filesystem;

namespace {

std::string default_report(const std::string& output) {
  fs::path p(output);
  return (p.parent_path() / (p.stem().string() + "_report")).string();
}

std::string g(double v, int digits = 4) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace

const ConfigSchema& diagnose_schema() {
  static const ConfigSchema schema = with_keys_after("label", measurement_keys(), ConfigSchema{
      "diagnose-vehs",
      "Diagnoses a model (docs/model-file.md) against measured displacement records: how well does it "
      "reproduce them, and where exactly does it fail? Data and, for every record, twins simulated "
      "from the model (same duration, sampling, initial state, drive and measurement process) go "
      "through identical statistics — whitened one-step residuals mapped over (x, v), their spectrum, "
      "p(x, v), E[X^2], E[v^2], well probabilities and transition rates, the spectrum of x — compared "
      "unit by unit with calibrated tests. Writes a JSON verdict and score (docs/outputs.md#diagnosis-file), a report "
      "folder (HTML page with gnuplot figures, their CSVs and scripts) and appends to the model history. "
      "Term-like effects missing from the model are fitted on the first part of every record and ranked "
      "by their held-out evidence (suspects).",
      {
          {"model", "path | object", "Model file to diagnose (docs/model-file.md), or the model inline.", ""},
          {"data", "path | [paths]", "Measurement files: CSV (t, x [, traj, u] columns; `#` comments, `,` `;` or tab delimiters), .npy (structured, or 2-D with `columns`) or .mat (here or in the `measurement` file). A path may be a glob pattern (\"run_*.csv\": the matching files in byte order, expanded by the tool, not a shell; a pattern that matches nothing is an error naming it).", ""},
          {"output", "path", "JSON summary to write (atomically): verdict, score, components, suspects and details.", ""},
          {"report", "path", "Report folder (index.html, figures as SVG with their CSV data and gnuplot scripts, summary.json, history).",
           "<output without .json>_report"},
          {"refit", "path",
           "The identify-vehs config of the next fit, written when the diagnosis recommends effects: the "
           "diagnosed model's terms with the recommended effects, this config's data keys and output "
           "refit_model.json beside it; run it as it is (identify-vehs <report>/refit.json).",
           "<report>/refit.json"},
          {"history", "path", "Model history file appended by every run (the report plots the score over model versions); runs sharing it take turns (lock file <history>.lock while one appends).",
           "<report>/history.json"},
          {"label", "string", "Name of this model version in the history and the report.", "the model file's name"},
          {"seed", "integer", "Seed of the twins and refits (results are reproducible and independent of the thread count).", "1"},
          {"replicates", "integer", "Twins per record; 0 chooses enough for at least 2e6 twin samples (1 to 8).", "0"},
          {"bins", "{\"x\", \"v\"}", "Bins of the one-step map over x and the lens velocity v (quantile range of the data).",
           "{\"x\": 16, \"v\": 16}"},
          {"min_bin_count", "number", "Rows a map bin needs on each side to enter the one-step test.", "200"},
          {"min_units", "integer",
           "With fewer records than this, every record is cut into time blocks treated as independent units.", "32"},
          {"holdout", "number", "Fraction at the end of every record held out to score the suspects.", "0.3"},
          {"user_effects", "[{name, drift, diffusion}]",
           "Your own effects, tested as suspects beside the catalogue's (score test, held-out refit, confirmation) "
           "and recommended by name: each {\"name\": ..., \"drift\": {\"param\": \"term\", ...}, \"diffusion\": "
           "{...}}, every parameter the coefficient of its term (an expression in x, y, u), as in identify-vehs's "
           "effects (docs/model-file.md#user-effects).",
           "[]"},
          {"suspects", "bool | object",
           "Rank missing effects: true/false, or {\"z_threshold\": 3, \"min_blocks\": 20, \"effects\": [names], "
           "\"confirm\": true} (significance of the held-out gain, held-out blocks for its standard error, effects "
           "to try, confirm colored_noise against deterministic slow forces by refits).",
           "true"},
          {"suspect_samples", "number",
           "The suspects use whole records, in order, up to this many samples (their refits are the slowest "
           "part of a run); 0: all data.",
           "4e6"},
          {"score_suspects", "bool | object",
           "Likelihood score tests of every effect the model lacks, on all the data: true/false, or {\"grid\": 6 "
           "(values of a gap, lambda or tau scanned), \"max_samples\": 2.5e5 (whole records up to this many "
           "samples; 0: all), \"forcing_band\": 6 (harmonic forcing scanned up to this multiple of the data's "
           "typical frequency)}.",
           "true"},
          {"confirm", "bool | object",
           "Before an effect is recommended for an inadequate model, refit the model with it on the first part of "
           "every record and check the held-out rest: the one-step likelihood must improve, or be what the "
           "all-data score test predicts for the held-out share; a driven model's free-run RMSE must improve where "
           "the free run predicts the response, else not get worse: true/false, or {\"holdout\": 0.3, "
           "\"blocks\": 8 (held-out pieces), \"z_threshold\": 2, \"consistency_margin\": 2.5 (standard errors "
           "below the predicted held-out z), \"max_samples\": 2.5e5 (whole records up to this many samples; 0: "
           "all), \"max_effects\": 8}.",
           "true"},
          {"alpha", "number", "Family-wise level of the verdict (Bonferroni over the components).", "0.01"},
          {"lens", "string",
           "Kinematics: auto (the model file's estimator, else the data's sampling diagnosis), forward (data from "
           "an explicit scheme at the recorded step), central (a sensor sampling a continuous process).",
           "\"auto\""},
          {"stride", "integer", "Stride of the central kinematics (0: the model file's, else 1).", "0"},
          {"sensor_noise", "number",
           "Standard deviation of white sensor noise on x assumed for the lens and the twins (default: the model "
           "file's likelihood.measurement_sd or sampling.sensor_noise_sd, else the data's sampling diagnosis); > 0: "
           "the data are read as a noisy sensor of a continuous process. Data whose values lie on a grid (ADC counts, "
           "fixed decimals) get twins rounded to that grid, with white noise only for the part beyond the rounding's "
           "q^2/12, and the held-out suspects stand aside where the rounding is correlated over the first strides.",
           "", true},
          {"twin_scheme", "string",
           "Scheme of the twins: auto (rk4_euler at the recorded step for scheme-consistent data, taylor15 on "
           "substeps otherwise), euler_maruyama, rk4_euler, baoab, taylor15.",
           "\"auto\""},
          {"twin_substeps", "integer",
           "Internal steps per sample of the twins (0: 1 for scheme-consistent data, else enough that rho*h <= "
           "0.02 with rho the model's fastest linearised rate where the data are, at least 10).",
           "0"},
          {"residual_lags", "integer", "Lags of the residual autocorrelation figure.", "64"},
          {"parameter_uncertainty", "string",
           "Include the model's parameter uncertainty in the stationary and x-spectrum tests (refit its terms on "
           "pseudo-data simulated from it): auto (when the model file reports standard errors), on, off.",
           "\"auto\""},
          {"parameter_draws", "integer", "Refits behind the parameter uncertainty.", "8"},
          {"parameter_fit_samples", "number", "Samples of each refit (the covariance is rescaled to the data size).", "2e6"},
          {"fpk", "bool", "Solve the model's stationary Fokker-Planck equation as a reference curve.", "true"},
          {"fpk_cells", "integer", "FPK cells per axis (doubled, up to 800, when they do not resolve the model; the report says so, and a reference that cannot be solved is a warning).", "160"},
          {"check_model_sampling", "bool",
           "Error when the model file says it was identified from data sampled at another interval.", "true"},
          {"fail_on_inadequate", "bool",
           "Exit with status 3 when the verdict is inadequate (for scripts; the flag --fail-on-inadequate sets it).",
           "false"},
      },
      "Outputs: the JSON at `output` (verdict, score, components, suspects; tests with p-values, the one-step "
      "map's worst bins and failure region, quantities, timings), the report folder and the history file. Exit "
      "status 0 for either verdict (3 for inadequate with fail_on_inadequate), 1 for bad input.\n"
      "Example: diagnose-vehs data/diagnose/paper.json --set model='\"out/paper/learned.json\"'"});
  return schema;
}

namespace {

/// A copy of the page in <folder>/versions/v<version>.html (the page is self-contained: its
/// figures are embedded), with the links between versions made relative to that folder.
void keep_version_page(const std::string& html, const std::string& folder, int version) {
  std::ifstream in(current_output_path(html), std::ios::binary);  // (staged in this run's transaction)
  std::stringstream ss;
  ss << in.rdbuf();
  std::string page = ss.str();
  const std::string from = "href=\"versions/", to = "href=\"";
  for (auto p = page.find(from); p != std::string::npos; p = page.find(from, p + to.size()))
    page.replace(p, from.size(), to);
  write_file_atomically((fs::path(folder) / "versions" / ("v" + std::to_string(version) + ".html")).string(), page);
}

}  // namespace

diagnose::Options diagnose_options(const Config& c) {
  Options o;
  o.seed = static_cast<std::uint64_t>(c.integer_at_least("seed", 0, 1));
  o.replicates = c.int_at_least("replicates", 0, 0);
  if (o.replicates > 1000) c.fail("replicates", "must be <= 1000");
  if (c.has("bins")) {
    const Config b = c.object("bins", {"x", "v"});
    o.map_bins_x = b.int_at_least("x", 2, 16);
    o.map_bins_v = b.int_at_least("v", 2, 16);
    if (o.map_bins_x > 200 || o.map_bins_v > 200) c.fail("bins", "at most 200 per axis");
  }
  o.min_bin_count = c.positive_or("min_bin_count", 200);
  if (o.min_bin_count < 10) c.fail("min_bin_count", "must be >= 10");
  o.min_units = c.int_at_least("min_units", 4, 32);
  o.suspects.holdout = c.positive_or("holdout", 0.3);
  if (!(o.suspects.holdout > 0.05 && o.suspects.holdout < 0.95)) c.fail("holdout", "must be in (0.05, 0.95)");
  if (c.has("suspects")) {
    const auto& v = c.raw("suspects");
    if (v.is_boolean()) {
      o.suspects.enabled = v.get<bool>();
    } else if (v.is_object()) {
      const Config s = c.object("suspects", {"z_threshold", "min_blocks", "effects", "enabled", "confirm"});
      o.suspects.enabled = s.boolean_or("enabled", true);
      o.suspects.confirm = s.boolean_or("confirm", true);
      o.suspects.z_threshold = s.positive_or("z_threshold", 3.0);
      o.suspects.min_blocks = s.int_at_least("min_blocks", 2, 20);
      if (s.has("effects"))
        for (const auto& name : s.string_list("effects"))
          o.suspects.only.push_back(enum_from_string(kEffectNames, name, s.where("effects")));
    } else {
      c.fail("suspects", "must be true, false or an object");
    }
  }
  if (c.has("user_effects")) {
    const auto& list = c.raw("user_effects");
    if (!list.is_array()) c.fail("user_effects", "must be a list of {\"name\": ..., \"drift\": {...}}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string where = c.where("user_effects") + "[" + std::to_string(i) + "]";
      o.user_effects.push_back(user_effect_from_json(list[i], where));
      if (find_user_effect(o.user_effects, o.user_effects.back().name) != &o.user_effects.back())
        throw Error(where + ": '" + o.user_effects.back().name + "' is listed twice");
    }
  }
  o.suspect_samples = c.non_negative_or("suspect_samples", 4e6);
  o.score_suspects.enabled = true;  // the product runs them (the library's default is off)
  if (c.has("score_suspects")) {
    const auto& v = c.raw("score_suspects");
    if (v.is_boolean()) {
      o.score_suspects.enabled = v.get<bool>();
    } else if (v.is_object()) {
      const Config s = c.object("score_suspects", {"enabled", "grid", "max_samples", "forcing_band"});
      o.score_suspects.enabled = s.boolean_or("enabled", true);
      o.score_suspects.grid = s.int_at_least("grid", 1, 6);
      if (o.score_suspects.grid > 64) s.fail("grid", "must be <= 64");
      o.score_suspects.max_samples = s.non_negative_or("max_samples", 2.5e5);
      o.score_suspects.forcing_band = s.positive_or("forcing_band", 6.0);
    } else {
      c.fail("score_suspects", "must be true, false or an object");
    }
  }
  o.confirm.enabled = true;  // the product confirms before it recommends (the library's default is off)
  if (c.has("confirm")) {
    const auto& v = c.raw("confirm");
    if (v.is_boolean()) {
      o.confirm.enabled = v.get<bool>();
    } else if (v.is_object()) {
      const Config s = c.object("confirm", {"enabled", "holdout", "blocks", "z_threshold", "consistency_margin",
                                            "max_samples", "max_effects"});
      o.confirm.enabled = s.boolean_or("enabled", true);
      o.confirm.holdout = s.positive_or("holdout", 0.3);
      o.confirm.blocks = s.int_at_least("blocks", 3, 8);
      o.confirm.z_threshold = s.positive_or("z_threshold", 2.0);
      o.confirm.consistency_margin = s.positive_or("consistency_margin", 2.5);
      o.confirm.max_samples = s.non_negative_or("max_samples", 2.5e5);
      o.confirm.max_effects = s.int_at_least("max_effects", 1, 8);
      if (auto why = o.confirm.invalid_reason(); !why.empty()) c.fail("confirm", why);
    } else {
      c.fail("confirm", "must be true, false or an object");
    }
  }
  o.alpha = c.positive_or("alpha", 0.01);
  if (!(o.alpha < 0.5)) c.fail("alpha", "must be in (0, 0.5)");
  o.lens = enum_from_string(kLensNames, c.string_or("lens", "auto"), c.where("lens"));
  o.stride = c.int_at_least("stride", 0, 0);
  if (c.has("sensor_noise")) o.sensor_noise = c.non_negative_or("sensor_noise", 0.0);
  const std::string scheme = c.string_or("twin_scheme", "auto");
  if (scheme != "auto") {
    o.twin_scheme_auto = false;
    o.twin_scheme = enum_from_string(sim::kSchemeNames, scheme, c.where("twin_scheme") + " (or auto)");
  }
  o.twin_substeps = c.int_at_least("twin_substeps", 0, 0);
  o.residual_lags = c.int_at_least("residual_lags", 1, 64);
  o.parameter_uncertainty = enum_from_string(kParameterUncertaintyNames, c.string_or("parameter_uncertainty", "auto"),
                                             c.where("parameter_uncertainty"));
  o.parameter_draws = c.int_at_least("parameter_draws", 2, 8);
  o.parameter_fit_samples = c.positive_or("parameter_fit_samples", 2e6);
  o.fpk = c.boolean_or("fpk", true);
  o.fpk_cells = c.int_at_least("fpk_cells", 20, 160);
  o.check_model_sampling = c.boolean_or("check_model_sampling", true);
  if (c.has("dt")) o.expected_dt = c.positive("dt");
  if (auto why = o.invalid_reason(); !why.empty()) throw Error(c.file() + ": " + why);
  return o;
}

int run_diagnose(Config& c, const AppOptions& app) {
  const std::string output = c.path("output");
  const std::string folder = c.has("report") ? c.path("report") : default_report(output);
  const std::string history_path = c.has("history") ? c.path("history") : (fs::path(folder) / "history.json").string();
  diagnose::Options o = diagnose_options(c);
  o.progress = app.progress;
  read_history(history_path);  // fail before the work when the history file is not usable
  // model
  const auto& mv = c.raw("model");
  const std::string model_file = mv.is_string() ? mv.get<std::string>() : std::string("(inline)");
  const ModelFile model_file_content = model_from_config_value(mv, c.where("model"));
  const Model& model = model_file_content.model;
  validate_model(model, model_file);
  require(!model.drift.empty(), model_file + ": the model has no drift terms (a model file needs a 'drift' object)");
  require(!model.diffusion.empty(),
          model_file + ": the model has no diffusion terms (a model file needs a 'diffusion' object)");
  const std::string label =
      c.has("label") ? c.string("label") : (mv.is_string() ? fs::path(model_file).stem().string() : "inline model");
  // data
  const bool fail_on_inadequate = c.boolean_or("fail_on_inadequate", false);
  const auto files = c.path_list("data");
  const LoadedData loaded = load_measurements(c, model.uses_drive(), app);
  const Dataset& data = loaded.data;
  nlohmann::ordered_json units = units_block(c);
  if (units.empty() && model_file_content.sections.contains("units")) units = model_file_content.sections["units"];

  const diagnose::Result r = [&] {
    try {
      return diagnose::diagnose(model, data, o);
    } catch (const Error& e) {  // a model the simulator refuses: name its file (the one line of the error)
      const std::string what = e.what();
      if (what.rfind("simulating the model's twins", 0) == 0) throw Error(model_file + ": " + what);
      throw;
    }
  }();

  // history, report, JSON
  const auto entries = append_history(history_path, history_entry(model, model_file, label, data, r, model_file_content.sections));
  Report report(folder, "diagnose-vehs: " + label);
  const std::string fingerprint = data_fingerprint(data);
  const int version = entries.back().value("version", 0);
  std::vector<ReportLink> versions;  // every version's page is kept in <report>/versions/
  for (const auto& e : entries)
    if (e.value("data_fingerprint", "") == fingerprint) {
      const int v = e.value("version", 0);
      versions.push_back({"version " + std::to_string(v) + ": " + e.value("label", "") + " (" +
                              e.value("verdict", "") + (v == version ? ", this page)" : ")"),
                          "versions/v" + std::to_string(v) + ".html"});
    }
  // the next step as a config identify-vehs runs as it is (tools/refit_config.hpp)
  const std::string refit_path = refit_config_path(c, folder);
  const nlohmann::ordered_json refit = refit_identify_config(c, r, model, refit_path, units);
  const std::string refit_command = refit.is_null() ? "" : "identify-vehs " + refit_path;
  add_diagnosis_to_report(report, r, label, entries, fingerprint, units, versions, &model, &data, refit_command);
  nlohmann::ordered_json j = diagnosis_to_json(r, &model);
  j["model"] = model_file;
  j["label"] = label;
  j["data_files"] = files;
  j["data_reading"] = read_summary_json(loaded.summary);
  if (!units.empty()) j["units"] = units;
  j["report"] = folder;
  j["history"] = history_path;
  j["version_in_history"] = entries.back().value("version", 0);
  j["config"] = c.json();
  j["provenance"] = {{"tool", "diagnose-vehs"}, {"library", library_version()}};
  j["refit_file"] = refit.is_null() ? nlohmann::ordered_json() : nlohmann::ordered_json(refit_path);
  if (!refit.is_null()) {
    write_json_atomically(refit_path, refit);
  } else {  // a config of an earlier run would be a wrong next step now
    std::error_code ec;
    fs::remove(refit_path, ec);
  }
  write_json_atomically((fs::path(folder) / "summary.json").string(), j);
  const std::string html = report.write_html();
  keep_version_page(html, folder, version);
  write_json_atomically(output, j);
  if (!app.quiet) {
    std::printf("verdict: %s   score %s (adequate models score about %s)\n", enum_to_string(diagnose::kVerdictNames, r.verdict).c_str(), g(r.score).c_str(),
                g(r.score_expected_adequate, 2).c_str());
    for (const auto& comp : r.components)
      std::printf("  %-18s %s\n", comp.name.c_str(),
                  comp.test.available ? ("p = " + g(comp.test.p_value, 3) + ", size " + g(comp.test.excess, 3) +
                                         (comp.test.p_value < r.threshold ? "  FAILED" : ""))
                                            .c_str()
                                      : ("not available: " + comp.test.note).c_str());
    std::printf("model parameters:\n%s", parameter_table(model, units, "  ").c_str());
    // held-out suspects of a split set aside come last: they are not a test on these data
    const bool aside = !r.suspects.set_aside.empty();
    const auto print_heldout = [&] {
      if (r.suspects.ranked.empty()) return;
      std::printf("suspects (held-out evidence, nats)%s:\n",
                  aside ? "; SET ASIDE, not a test on these data (see the report)" : "");
      for (const auto& s : r.suspects.ranked)
        std::printf("  %-26s %10s  z = %6s%s\n", s.effect.c_str(), g(s.evidence).c_str(), g(s.z, 3).c_str(),
                    aside ? "  set aside"
                    : s.significant ? "  claimed"
                    : !s.outside_domain.empty() ? ("  not claimed: " + s.outside_domain).c_str()
                                                : "");
    };
    if (!aside) print_heldout();
    if (!r.score_suspects.ranked.empty()) {
      std::printf("score suspects (likelihood, all data):\n");
      for (const auto& s : r.score_suspects.ranked)
        std::printf("  %-28s z = %6s  p = %-9s power %s%s\n", s.effect.c_str(), g(s.z, 3).c_str(),
                    g(s.p_value, 2).c_str(), g(s.power, 2).c_str(), s.significant ? "  significant" : "");
    }
    if (r.confirmation.ran) {
      std::printf("confirmation by held-out refits (%s):\n", r.confirmation.criterion.c_str());
      for (const auto& e : r.confirmation.effects) std::printf("  %-28s %s\n", e.effect.c_str(), e.reason.c_str());
    }
    if (aside) print_heldout();
    for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());
    std::printf("conclusion: %s\n", r.conclusion.c_str());
    if (!refit_command.empty())
      std::printf("Next step: add %s: run  %s\n", j["recommended"].dump().c_str(), refit_command.c_str());
    else
      std::printf("%s\n", next_step(r, &model).c_str());
    if (!refit.is_null()) std::printf("refit config: %s (run it: identify-vehs %s)\n", refit_path.c_str(), refit_path.c_str());
    std::printf("report: %s\nsummary: %s\n", html.c_str(), output.c_str());
  }
  return fail_on_inadequate && r.verdict == diagnose::Verdict::Inadequate ? 3 : 0;
}

}  // namespace vehs::tools
