#include "tools/diagnosis_file.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/io/model_file.hpp"

namespace vehs::tools {

namespace {
using J = nlohmann::ordered_json;
J num(double v) { return std::isfinite(v) ? J(v) : J(); }
}  // namespace

std::string verdict_text(SamplingVerdict v) {
  return v == SamplingVerdict::Unknown ? "" : enum_to_string(kSamplingVerdictNames, v);
}

std::string estimator_text(Estimator e) { return e == Estimator::Auto ? "" : enum_to_string(kEstimatorNames, e); }

nlohmann::ordered_json suspect_add_fragment(const diagnose::Suspect& s, const std::vector<UserEffect>& user) {
  if (const UserEffect* u = find_user_effect(user, s.effect)) return {{"effects", J::array({user_effect_to_json(*u)})}};
  return {{"effects", J::array({{{"name", s.effect}}})}};
}

namespace {
J confirmation_to_json(const diagnose::ConfirmationReport& c) {
  J j;
  j["ran"] = c.ran;
  if (!c.note.empty()) j["note"] = c.note;
  j["criterion"] = c.criterion;
  j["driven"] = c.driven;
  if (c.driven) {
    j["free_run_informative"] = c.free_run_informative;
    j["heldout_sd"] = num(c.heldout_sd);
  }
  j["train_samples"] = c.train_samples;
  j["heldout_samples"] = c.heldout_samples;
  j["pieces"] = c.pieces;
  j["baseline_loglik"] = num(c.baseline_loglik);
  j["baseline_rmse"] = num(c.baseline_rmse);
  J effects = J::array();
  for (const auto& e : c.effects) {
    J x;
    x["effect"] = e.effect;
    if (e.per_record_phase) x["per_record_phase"] = true;
    x["evidence"] = e.evidence;
    x["confirmed"] = e.confirmed;
    x["loglik_gain"] = num(e.loglik_gain);
    x["loglik_z"] = num(e.loglik_z);
    x["all_data_z"] = num(e.all_data_z);
    x["expected_z"] = num(e.expected_z);
    x["by_consistency"] = e.by_consistency;
    if (!e.refit_innovations.empty()) x["refit_innovations"] = e.refit_innovations;
    x["rmse"] = num(e.rmse_effect);
    x["rmse_z"] = num(e.rmse_z);
    x["params"] = e.params;
    x["params_stderr"] = e.params_stderr;
    if (!e.error.empty()) x["error"] = e.error;
    x["reason"] = e.reason;
    effects.push_back(x);
  }
  j["effects"] = effects;
  const auto& s = c.residuals;
  j["residuals"] = {{"summary", s.summary},
                    {"samples", s.samples},
                    {"variance", num(s.variance)},
                    {"lag1", num(s.lag1)},
                    {"lag1_z", num(s.lag1_z)},
                    {"excess_kurtosis", num(s.excess_kurtosis)},
                    {"kurtosis_z", num(s.kurtosis_z)},
                    {"heteroscedasticity", num(s.heteroscedasticity)},
                    {"heteroscedastic_in", s.heteroscedastic_in},
                    {"heteroscedasticity_z", num(s.heteroscedasticity_z)},
                    {"input_correlation", num(s.input_correlation)},
                    {"input_lag", s.input_lag},
                    {"input_z", num(s.input_z)},
                    {"line_frequency", num(s.line_frequency)},
                    {"line_z", num(s.line_z)}};
  j["seconds"] = c.seconds;
  return j;
}
}  // namespace

nlohmann::ordered_json refit_config(const diagnose::Result& r, const Model& model) {
  if (!r.confirmation.ran || r.recommended.empty()) return nullptr;
  J cfg;
  J drift = J::array(), diffusion = J::array(), effects = J::array();
  for (const auto& tc : model.drift) drift.push_back(tc.term.name());
  for (const auto& tc : model.diffusion) diffusion.push_back(tc.term.name());
  for (const auto& e : model.effects) effects.push_back(e.name());
  for (const auto& name : r.recommended)
    if (const UserEffect* u = find_user_effect(r.user_effects, name)) effects.push_back(user_effect_to_json(*u));
    else if (std::find(effects.begin(), effects.end(), J(name)) == effects.end()) effects.push_back(name);
  cfg["drift_library"] = drift;
  cfg["diffusion_library"] = diffusion;
  cfg["effects"] = effects;
  cfg["sparsity"] = "none";
  if (r.confirmation.by_likelihood) {
    J lik;
    if (!(model.fit && model.fit->likelihood)) lik["use"] = "always";
    lik["select"] = false;
    // the input's interpolation as the likelihood chose it (a moment fit's default "zoh" is no choice)
    if (model.fit && model.fit->likelihood && model.uses_drive())
      lik["input"] = enum_to_string(kInputInterpolationNames, model.fit->input);
    for (const auto& c : r.confirmation.effects)
      if (c.confirmed && c.per_record_phase) lik["per_record_phase"] = true;
    cfg["likelihood"] = lik;
  }
  return cfg;
}

nlohmann::ordered_json diagnosis_to_json(const diagnose::Result& r, const Model* model) {
  using namespace vehs::diagnose;
  J j;
  j["verdict"] = enum_to_string(diagnose::kVerdictNames, r.verdict);
  j["conclusion"] = r.conclusion;
  j["recommended"] = r.recommended;
  if (model) j["refit_config"] = refit_config(r, *model);
  j["outside_catalogue"] = r.outside_catalogue;
  j["score"] = r.score;
  J comp = J::object();
  for (const auto& c : r.components) comp[c.name] = c.test.available ? J(c.test.excess) : J();
  j["components"] = comp;
  J sus = J::array();
  for (const auto& s : r.suspects.ranked) {
    J e;
    e["effect"] = s.effect;
    e["evidence"] = num(s.evidence);
    e["params"] = s.params;
    e["add"] = suspect_add_fragment(s, r.user_effects);
    if (!s.outside_domain.empty()) e["outside_domain"] = s.outside_domain;
    e["z"] = num(s.z);
    e["significant"] = s.significant;
    e["held_out_significant"] = s.held_out_significant;
    e["scale"] = s.scale;
    e["params_stderr"] = s.params_stderr;
    e["terms"] = s.terms;
    if (const std::string refit = refit_text(s); !refit.empty()) e["refit"] = {{"verdict", refit}, {"score", num(s.refit_score)}};
    sus.push_back(e);
  }
  j["suspects"] = sus;
  J score = J::array();
  for (const auto& s : r.score_suspects.ranked) {
    J e;
    e["effect"] = s.effect;
    e["z"] = num(s.z);
    e["p_value"] = num(s.p_value);
    e["significant"] = s.significant;
    e["statistic"] = num(s.statistic);
    e["dof"] = num(s.dof);
    e["test"] = s.test;
    e["params"] = s.params;
    e["params_stderr"] = s.params_stderr;
    if (const UserEffect* u = find_user_effect(r.user_effects, s.effect)) e["add"] = {{"effects", J::array({user_effect_to_json(*u)})}};
    else e["add"] = J::parse(s.add);
    e["null_claim_rate"] = num(s.null_claim_rate);
    e["power"] = num(s.power);
    if (!s.detectable.empty()) e["detectable"] = s.detectable;
    if (!s.not_resolved_from.empty()) e["not_resolved_from"] = s.not_resolved_from;
    if (const auto& la = s.look_alikes; !la.compared.empty())
      e["look_alikes"] = {{"compared", la.compared},       {"log_likelihoods", la.log_likelihoods},
                          {"two_delta_log_l", num(la.two_delta_log_l)},
                          {"resolved", la.resolved},       {"data_needed", num(la.data_needed)},
                          {"rule", la.rule}};
    score.push_back(e);
  }
  j["score_suspects"] = score;
  j["confirmation"] = confirmation_to_json(r.confirmation);
  // ---- details
  j["score_definition"] =
      "sum over the available components of max(0, chi2/dof - 1), chi2 the chi-square quantile "
      "(dof degrees of freedom) of the component's p-value: about 0 for an adequate model, growing "
      "with the misfit and the amount of data; lower is better";
  j["score_expected_if_adequate"] = r.score_expected_adequate;
  j["verdict_rule"] = "inadequate when a component's p-value is below alpha / (available components)";
  j["threshold"] = r.threshold;
  J tests = J::object();
  for (const auto& c : r.components) {
    J t;
    t["what"] = c.what;
    t["available"] = c.test.available;
    t["p_value"] = c.test.available ? num(c.test.p_value) : J();
    t["chi2"] = c.test.available ? num(c.test.chi2) : J();
    t["dof"] = c.test.dof;
    t["statistic"] = c.test.available ? num(c.test.statistic) : J();
    t["excess"] = c.test.excess;
    t["units"] = c.test.units;
    t["method"] = c.test.method;
    if (!c.test.note.empty()) t["note"] = c.test.note;
    t["failed"] = c.test.available && c.test.p_value < r.threshold;
    tests[c.name] = t;
  }
  j["tests"] = tests;
  j["lens"] = {{"kinematics", r.lens.kinematics == Kinematics::Central ? "central" : "forward"},
               {"stride", r.lens.stride},
               {"dt", r.lens.dt},
               {"sensor_noise_sd", r.lens.sensor_noise_sd},
               {"description", r.lens.describe()}};
  j["sampling"] = {{"data_verdict", verdict_text(r.sampling.data_verdict)},
                   {"model_verdict", verdict_text(r.sampling.model_verdict)},
                   {"model_estimator", estimator_text(r.sampling.model_estimator)},
                   {"data_dt", r.sampling.data_dt},
                   {"model_dt", num(r.sampling.model_dt > 0 ? r.sampling.model_dt : NAN)},
                   {"twin_scheme", enum_to_string(sim::kSchemeNames, r.sampling.twin_scheme)},
                   {"twin_substeps", r.sampling.twin_substeps},
                   {"replicates", r.sampling.replicates}};
  j["data"] = {{"records", r.records}, {"samples", r.samples}, {"rows", r.rows}, {"units", r.units}, {"unit_kind", r.unit_kind}};
  j["parameter_uncertainty"] = {
      {"refits", r.parameter_draws},
      {"samples_per_refit", r.parameter_fit_samples},
      {"method", r.parameter_draws > 0
                     ? "the model's terms refitted by identify on pseudo-data simulated from the model, "
                       "resimulated with common random numbers; the covariance of the shift of the "
                       "stationary and x-spectrum statistics (rescaled to the data size) is added to "
                       "their tests"
                     : "not used (the model reports no standard errors, or parameter_uncertainty is off)"}};
  J worst = J::array();
  for (int b : r.map.worst) {
    const MapBin& m = r.map.bins[static_cast<std::size_t>(b)];
    worst.push_back({{"x", m.x}, {"v", m.v}, {"z_mean", m.z_mean}, {"mean_data", m.mean_data},
                     {"mean_twin", m.mean_twin}, {"z_log_variance", m.z_var}, {"var_data", m.var_data},
                     {"var_twin", m.var_twin}, {"rows_data", m.n_data}});
  }
  int used = 0;
  for (const auto& b : r.map.bins) used += b.used;
  auto vec = [](const std::vector<double>& v) {
    J a = J::array();
    for (double x : v) a.push_back(std::isfinite(x) ? J(x) : J());
    return a;
  };
  auto argmax = [](const std::vector<double>& v) {
    int k = -1;
    for (std::size_t i = 0; i < v.size(); ++i)
      if (std::isfinite(v[i]) && (k < 0 || v[i] > v[static_cast<std::size_t>(k)])) k = static_cast<int>(i);
    return k;
  };
  const double wx = (r.map.x_hi - r.map.x_lo) / std::max(r.map.nx, 1), wv = (r.map.v_hi - r.map.v_lo) / std::max(r.map.nv, 1);
  const int km = argmax(r.map.v_profile_mean), kx = argmax(r.map.x_profile_mean);
  j["one_step_map"] = {
      {"bins_x", r.map.nx}, {"bins_v", r.map.nv}, {"x_range", {r.map.x_lo, r.map.x_hi}},
      {"v_range", {r.map.v_lo, r.map.v_hi}}, {"bins_used", used},
      {"worst_bins", worst},
      {"failure_region",
       {{"v_column_center", km >= 0 ? J(r.map.v_lo + (km + 0.5) * wv) : J()},
        {"x_row_center", kx >= 0 ? J(r.map.x_lo + (kx + 0.5) * wx) : J()},
        {"explanation", "centres of the v column and x row with the largest mean z^2 of the residual mean"}}},
      {"v_profile_mean_z2", vec(r.map.v_profile_mean)},
      {"v_profile_var_z2", vec(r.map.v_profile_var)},
      {"x_profile_mean_z2", vec(r.map.x_profile_mean)},
      {"x_profile_var_z2", vec(r.map.x_profile_var)}};
  J q = J::array();
  for (const auto& x : r.quantities)
    q.push_back({{"name", x.name}, {"data", num(x.data)}, {"data_se", num(x.data_se)}, {"twin", num(x.twin)},
                 {"twin_se", num(x.twin_se)}, {"z", num(x.z)}, {"fpk", num(x.reference)}});
  j["quantities"] = q;
  j["hellinger"] = {{"p(x)", r.hellinger_px},
                    {"p(x,v)", r.hellinger_pxy},
                    {"p(x) twin vs twin", r.hellinger_px_null >= 0 ? J(r.hellinger_px_null) : J()},
                    {"p(x,v) twin vs twin", r.hellinger_pxy_null >= 0 ? J(r.hellinger_pxy_null) : J()}};
  J w = J::array();
  for (const auto& x : r.wells)
    w.push_back({{"x_min", x.x_min}, {"lo", num(x.lo)}, {"hi", num(x.hi)}, {"core", {x.core_lo, x.core_hi}}});
  j["wells"] = w;
  j["fpk"] = r.fpk_note;
  J un = J::array();
  for (const auto& [name, why] : r.suspects.untested) un.push_back({{"effect", name}, {"reason", why}});
  j["untested_effects"] = un;
  if (!r.suspects.note.empty()) j["suspects_note"] = r.suspects.note;
  {
    J un2 = J::array();
    for (const auto& [name, why] : r.score_suspects.untested) un2.push_back({{"effect", name}, {"reason", why}});
    j["score_suspects_details"] = {{"samples", r.score_suspects.samples},
                                   {"records", r.score_suspects.records},
                                   {"threshold", r.score_suspects.threshold},
                                   {"untested", un2},
                                   {"note", r.score_suspects.note}};
  }
  j["suspects_heldout"] = {{"rows", r.suspects.baseline_heldout_rows}, {"blocks", r.suspects.blocks}};
  if (!r.suspects.set_aside.empty()) j["suspects_heldout"]["set_aside"] = r.suspects.set_aside;
  j["warnings"] = r.warnings;
  J timings = J::object();
  for (const auto& [stage, seconds] : r.timings) timings[stage] = seconds;
  j["timings"] = timings;
  return j;
}

}  // namespace vehs::tools
