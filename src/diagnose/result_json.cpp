#include <algorithm>
#include <cmath>

#include "vehs/diagnose/diagnose.hpp"

namespace vehs::diagnose {

namespace {
using J = nlohmann::ordered_json;
J num(double v) { return std::isfinite(v) ? J(v) : J(); }
}  // namespace

nlohmann::ordered_json Result::to_json() const {
  J j;
  j["verdict"] = verdict;
  j["score"] = score;
  J comp = J::object();
  for (const auto& c : components) comp[c.name] = c.test.available ? J(c.test.excess) : J();
  j["components"] = comp;
  J sus = J::array();
  for (const auto& s : suspects.ranked) {
    J e;
    e["effect"] = s.effect;
    e["evidence"] = num(s.evidence);
    e["params"] = s.params;
    e["add"] = s.add;
    e["z"] = num(s.z);
    e["significant"] = s.significant;
    e["held_out_significant"] = s.held_out_significant;
    e["scale"] = s.scale;
    e["params_stderr"] = s.params_stderr;
    e["terms"] = s.terms;
    if (!s.refit_verdict.empty()) e["refit"] = {{"verdict", s.refit_verdict}, {"score", num(s.refit_score)}};
    sus.push_back(e);
  }
  j["suspects"] = sus;
  // ---- details
  j["score_definition"] =
      "sum over the available components of max(0, chi2/dof - 1), chi2 the chi-square quantile "
      "(dof degrees of freedom) of the component's p-value: about 0 for an adequate model, growing "
      "with the misfit and the amount of data; lower is better";
  j["score_expected_if_adequate"] = score_expected_adequate;
  j["verdict_rule"] = "inadequate when a component's p-value is below alpha / (available components)";
  j["threshold"] = threshold;
  J tests = J::object();
  for (const auto& c : components) {
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
    t["failed"] = c.test.available && c.test.p_value < threshold;
    tests[c.name] = t;
  }
  j["tests"] = tests;
  j["lens"] = {{"kinematics", lens.kinematics == Kinematics::Central ? "central" : "forward"},
               {"stride", lens.stride},
               {"dt", lens.dt},
               {"sensor_noise_sd", lens.sensor_noise_sd},
               {"description", lens.describe()}};
  j["sampling"] = {{"data_verdict", sampling.data_verdict},
                   {"model_verdict", sampling.model_verdict},
                   {"model_estimator", sampling.model_estimator},
                   {"data_dt", sampling.data_dt},
                   {"model_dt", num(sampling.model_dt > 0 ? sampling.model_dt : NAN)},
                   {"twin_scheme", sampling.twin_scheme},
                   {"twin_substeps", sampling.twin_substeps},
                   {"replicates", sampling.replicates}};
  j["data"] = {{"records", records}, {"samples", samples}, {"rows", rows}, {"units", units}, {"unit_kind", unit_kind}};
  j["parameter_uncertainty"] = {
      {"refits", parameter_draws},
      {"samples_per_refit", parameter_fit_samples},
      {"method", parameter_draws > 0
                     ? "the model's terms refitted by identify on pseudo-data simulated from the model, "
                       "resimulated with common random numbers; the covariance of the shift of the "
                       "stationary and x-spectrum statistics (rescaled to the data size) is added to "
                       "their tests"
                     : "not used (the model reports no standard errors, or parameter_uncertainty is off)"}};
  J worst = J::array();
  for (int b : map.worst) {
    const MapBin& m = map.bins[static_cast<std::size_t>(b)];
    worst.push_back({{"x", m.x}, {"v", m.v}, {"z_mean", m.z_mean}, {"mean_data", m.mean_data},
                     {"mean_twin", m.mean_twin}, {"z_log_variance", m.z_var}, {"var_data", m.var_data},
                     {"var_twin", m.var_twin}, {"rows_data", m.n_data}});
  }
  int used = 0;
  for (const auto& b : map.bins) used += b.used;
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
  const double wx = (map.x_hi - map.x_lo) / std::max(map.nx, 1), wv = (map.v_hi - map.v_lo) / std::max(map.nv, 1);
  const int km = argmax(map.v_profile_mean), kx = argmax(map.x_profile_mean);
  j["one_step_map"] = {
      {"bins_x", map.nx}, {"bins_v", map.nv}, {"x_range", {map.x_lo, map.x_hi}},
      {"v_range", {map.v_lo, map.v_hi}}, {"bins_used", used},
      {"worst_bins", worst},
      {"failure_region",
       {{"v_column_center", km >= 0 ? J(map.v_lo + (km + 0.5) * wv) : J()},
        {"x_row_center", kx >= 0 ? J(map.x_lo + (kx + 0.5) * wx) : J()},
        {"explanation", "centres of the v column and x row with the largest mean z^2 of the residual mean"}}},
      {"v_profile_mean_z2", vec(map.v_profile_mean)},
      {"v_profile_var_z2", vec(map.v_profile_var)},
      {"x_profile_mean_z2", vec(map.x_profile_mean)},
      {"x_profile_var_z2", vec(map.x_profile_var)}};
  J q = J::array();
  for (const auto& x : quantities)
    q.push_back({{"name", x.name}, {"data", num(x.data)}, {"data_se", num(x.data_se)}, {"twin", num(x.twin)},
                 {"twin_se", num(x.twin_se)}, {"z", num(x.z)}, {"fpk", num(x.reference)}});
  j["quantities"] = q;
  j["hellinger"] = {{"p(x)", hellinger_px},
                    {"p(x,v)", hellinger_pxy},
                    {"p(x) twin vs twin", hellinger_px_null >= 0 ? J(hellinger_px_null) : J()},
                    {"p(x,v) twin vs twin", hellinger_pxy_null >= 0 ? J(hellinger_pxy_null) : J()}};
  J w = J::array();
  for (const auto& x : wells)
    w.push_back({{"x_min", x.x_min}, {"lo", num(x.lo)}, {"hi", num(x.hi)}, {"core", {x.core_lo, x.core_hi}}});
  j["wells"] = w;
  j["fpk"] = fpk_note;
  J un = J::array();
  for (const auto& [name, why] : suspects.untested) un.push_back({{"effect", name}, {"reason", why}});
  j["untested_effects"] = un;
  if (!suspects.note.empty()) j["suspects_note"] = suspects.note;
  j["suspects_heldout"] = {{"rows", suspects.baseline_heldout_rows}, {"blocks", suspects.blocks}};
  j["warnings"] = warnings;
  j["timings"] = timings;
  return j;
}

}  // namespace vehs::diagnose
