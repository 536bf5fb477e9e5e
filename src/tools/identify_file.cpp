#include "tools/identify_file.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vehs/io/model_file.hpp"

namespace vehs::tools {

namespace {

using J = nlohmann::ordered_json;
using namespace vehs::identify;

J num_or_null(double v) { return std::isfinite(v) ? J(v) : J(); }

J estimator_json(const FitInfo& fit, const EstimatorChoice& e) {
  const bool central = uses_central_kinematics(fit.estimator);
  const char* target = fit.estimator == Estimator::Paper ? "raw Kramers-Moyal (y[i+1] - y[i])^2/dt, ordinary least squares"
                       : fit.estimator == Estimator::Noisy
                           ? "(12/11) h (r[i]^2 + 1.5 r[i] r[i+k]), weighted least squares"
                       : central ? "(3/2) h * drift residual^2, weighted least squares"
                                 : "dt * drift residual^2, weighted least squares";
  return {{"requested", enum_to_string(kEstimatorNames, e.requested)},
          {"used", enum_to_string(kEstimatorNames, fit.estimator)},
          {"reason", e.reason},
          {"stride", fit.stride},
          {"kinematics", central ? "central (ULI): v = (x[i+k] - x[i-k])/2h, a = (x[i+k] - 2x[i] + x[i-k])/h^2, h = k dt"
                                 : "forward: y = (x[i+1] - x[i])/dt, b = (y[i+1] - y[i])/dt"},
          {"ito_correction", central},
          {"discretization_correction", e.discretization_correction ? "target a - (h^2/12) x from a pilot drift" : "none"},
          {"diffusion_target", target},
          {"ssr_rule", enum_to_string(kSsrRuleNames, e.ssr_rule)}};
}

J sampling_json(const FitInfo& fit) {
  // the figures themselves are written by write_model_file from Model::fit (same keys, this order)
  J s;
  for (const char* key : {"dt", "pilot_stride", "rho_lag1", "rho_lag_k", "rho_lag_2k", "rho_lag_3k", "noise_share", "verdict"})
    s[key] = nullptr;
  if (fit.estimator == Estimator::Noisy || fit.sampling.sensor_noise_sd > 0.0) s["sensor_noise_sd"] = nullptr;
  if (fit.sampling.quantisation_step > 0.0) s["quantisation_step"] = nullptr;
  s["explanation"] =
      "lag autocorrelations of ULI residuals on a pilot subsample: about 0 at lag k for data from "
      "an explicit scheme at the recorded step, +1/4 for a sensor sampling a continuous process; "
      "white sensor noise pushes lag k toward -2/3 and lag 2k toward +1/6 but leaves lag 3k at 0, "
      "while a smooth unmodelled force raises lags k, 2k and 3k alike (noise share = 6 (rho_2k - rho_3k); for scheme-consistent data, whose lag-k base is 0, from lags k and 2k together)";
  return s;
}

J residuals_json(const ResidualReport& r) {
  J j;
  j["rows"] = r.rows;
  j["rms"] = r.rms;
  J ac = J::object();
  for (const auto& [lag, rho] : r.autocorrelation) ac["lag" + std::to_string(lag)] = rho;
  j["autocorrelation"] = ac;
  j["expected_lag_k"] = num_or_null(r.expected_lag_k);
  j["long_run_variance_factor_drift"] = r.long_run_factor_drift;
  j["long_run_variance_factor_diffusion"] = r.long_run_factor_diffusion;
  return j;
}

J path_json(const SelectionReport& report) {
  const SelectionResult& sel = report.selection;
  auto name = [&](int t) { return report.dictionary[static_cast<std::size_t>(t)].name(); };
  J steps = J::array();
  for (std::size_t s = 0; s < sel.path.size(); ++s) {
    const SupportFit& f = sel.path[s];
    J st;
    st["step"] = s;
    J coef = J::object();
    for (std::size_t i = 0; i < f.support.size(); ++i) coef[name(f.support[i])] = f.coef[static_cast<Eigen::Index>(i)];
    st["terms"] = coef;
    if (s + 1 < sel.path.size()) {
      J removed = J::array();
      const auto& next = sel.path[s + 1].support;
      for (int t : f.support)
        if (std::find(next.begin(), next.end(), t) == next.end()) removed.push_back(name(t));
      st["removed_next"] = removed;
    }
    st["bic"] = num_or_null(sel.bic[s]);
    st["cv_loss"] = num_or_null(sel.cv_loss[s]);
    st["cv_loss_minus_min"] = num_or_null(sel.cv_diff[s]);
    st["cv_loss_minus_min_se"] = num_or_null(sel.cv_diff_se[s]);
    st["condition"] = num_or_null(f.condition);
    steps.push_back(st);
  }
  J j;
  j["rule"] = sel.rule;
  j["chosen_step"] = sel.chosen;
  j["cv_min_step"] = sel.min_step;
  j["path"] = steps;
  return j;
}

/// The batches actually used: a batch ends at a fold or record boundary, so short records or
/// many folds give shorter batches than the target.
std::string stderr_method(const FitSummary& f) {
  const auto batches = static_cast<long long>(f.stderr_batches);
  const long long mean_rows = batches > 0 ? std::llround(static_cast<double>(f.rows) / f.stderr_batches) : 0;
  return "sandwich of the joint drift/diffusion estimating equations; batch means over " + std::to_string(batches) +
         " batches of " + std::to_string(mean_rows) + " rows on average (target " + std::to_string(f.stderr_batch_rows) +
         " rows per batch; a batch ends at a fold or record boundary)";
}

J fit_json(const FitSummary& f) {
  J j = {{"rows", f.rows},
         {"rows_left_out", f.rows_left_out},
         {"drift_condition_full_library", f.drift_condition_full},
         {"drift_condition_selected", num_or_null(f.drift_condition_selected)},
         {"diffusion_condition_full_library", f.diffusion_condition_full},
         {"stderr_method", stderr_method(f)}};
  j["seconds"] = f.seconds;
  J t = J::object();
  for (const auto& [stage, seconds] : f.timings) t[stage] = seconds;
  j["timings"] = t;
  return j;
}

J effect_with_stderr(const Effect& e) {
  J j = effect_to_json(e);
  if (!j.contains("stderr")) j["stderr"] = J::object();
  return j;
}

J profile_json(const ProfileFitReport& p) {
  J info;
  J search = J::object();
  for (const auto& c : p.search) {
    J ci = J::object();
    if (c.grid_quantile) ci["grid_quantile"] = *c.grid_quantile;
    if (c.lambda_grid) ci["grid"] = {(*c.lambda_grid)[0], (*c.lambda_grid)[1], static_cast<int>((*c.lambda_grid)[2])};
    if (c.spectrum_segment > 0) {
      ci["spectrum_segment"] = c.spectrum_segment;
      J lines = J::array();
      for (const auto& l : c.spectral_lines)
        lines.push_back({{"frequency", l.frequency}, {"peak_to_background", l.peak_to_background}});
      ci["spectral_lines"] = lines;
    }
    if (c.scan_step) ci["scan_step"] = *c.scan_step;
    search[enum_to_string(kEffectNames, c.effect)] = ci;
  }
  if (p.newton_iterations >= 0) search["newton_iterations"] = p.newton_iterations;
  info["search"] = search.empty() ? J() : search;  // null: a warm round that searched nothing
  info["rounds"] = p.rounds.size();
  for (std::size_t i = 0; i < p.rounds.size(); ++i) {
    const ProfileRound& r = p.rounds[i];
    std::string support;
    for (const auto& t : r.drift_terms) support += (support.empty() ? "" : ", ") + t.name();
    J effects = J::array();
    for (const auto& e : r.effects) effects.push_back(effect_to_json(e));
    info["round_" + std::to_string(i + 1)] = {{"estimator", enum_to_string(kEstimatorNames, r.estimator)},
                                              {"stride", r.stride},
                                              {"drift_terms", support},
                                              {"effects", effects},
                                              {"profile_contrast", r.profile_contrast}};
  }
  J effects = J::array();
  for (const auto& e : p.effects) effects.push_back(effect_to_json(e));
  info["effects"] = effects;
  info["profile_contrast"] = p.profile_contrast;
  info["rows"] = p.rows;
  if (p.samples_beyond_gap)
    info["impact_samples_beyond_gap"] = {{"positive", (*p.samples_beyond_gap)[0]}, {"negative", (*p.samples_beyond_gap)[1]}};
  info["method"] =
      "profile least squares of the Ito-corrected drift contrast over the nonlinear parameters "
      "(grid + golden section), linear parameters jointly with the drift terms; sandwich standard "
      "errors of (terms, linear, nonlinear) with batch means; then identify refits terms and "
      "diffusion with the fitted dynamic force subtracted from the target";
  return info;
}

J colored_json(const ColoredFitReport& c) {
  J rounds = J::array();
  for (const auto& r : c.rounds)
    rounds.push_back({{"tau", r.tau}, {"intensity", r.intensity}, {"lags", {r.lag_lo, r.lag_hi}}});
  J info;
  info["rounds"] = rounds;
  info["lags_fitted_s"] = {c.lag_lo_time, c.lag_hi_time};
  info["eta_variance_in_residual"] = c.eta_variance_in_residual;
  info["residual_variance"] = c.residual_variance;
  info["method"] =
      "colored_noise: tau and intensity from an exponential least-squares fit of the drift-residual "
      "autocovariance at lags >= 2 strides (tent kernels not overlapping); drift refitted by GLS on "
      "the prediction errors of a Kalman filter of the excitation (rows up to two strides back), "
      "iterated; white diffusion from the residual second moment minus the tent-averaged OU "
      "variance; standard errors: jackknife over contiguous batches (tau, intensity; drift held at "
      "its estimate), batch sandwich of the GLS equations (drift) and of the diffusion fit";
  return info;
}

}  // namespace

nlohmann::ordered_json identify_report_sections(const identify::Result& result) {
  const Report& rep = result.report;
  const FitInfo fit = result.model.fit.value_or(FitInfo{});
  J j;
  j["estimator"] = estimator_json(fit, rep.estimator);
  j["sampling"] = sampling_json(fit);
  j["residuals"] = residuals_json(rep.residuals);
  j["selection"] = {{"drift", path_json(rep.drift_selection)},
                    {"diffusion", path_json(rep.diffusion_selection)},
                    {"sparsity", enum_to_string(kSparsityNames, rep.sparsity)},
                    {"criterion", enum_to_string(kCriterionNames, rep.criterion)},
                    {"folds", rep.folds}};
  j["fit"] = fit_json(rep.fit);
  // effect_params: term-like effects are listed by identify's term fit (before the dynamic fit's
  // details); a fit with dynamic effects only lists them after its details
  J params = J::array();
  bool term_like = false;
  for (const auto& e : rep.effect_params) {
    params.push_back(effect_with_stderr(e));
    term_like = term_like || effect_spec(e.id).term_like;
  }
  for (const auto& u : rep.user_effect_params) {  // a user's effects: term-like
    params.push_back({{"name", u.name}, {"params", u.params}, {"stderr", u.stderr_}, {"user", true}});
    term_like = true;
  }
  if (term_like) j["effect_params"] = params;
  if (rep.profile) j["dynamic_fit"] = profile_json(*rep.profile);
  if (rep.colored) j["dynamic_fit"] = colored_json(*rep.colored);
  if (!term_like && !params.empty()) j["effect_params"] = params;
  return j;
}

}  // namespace vehs::tools
