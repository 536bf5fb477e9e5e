#include "physical_units.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

#include "estimator_choice.hpp"
#include "vehs/core/error.hpp"

namespace vehs::identify::detail {

namespace {

/// Coefficients of every step of a selection path over `dictionary`, scaled.
void scale_path(SelectionReport& r, double (*scale)(const Term&, const Scales&), const Scales& s) {
  for (auto& fit : r.selection.path)
    for (Eigen::Index j = 0; j < fit.coef.size() && j < static_cast<Eigen::Index>(fit.support.size()); ++j) {
      const int t = fit.support[static_cast<std::size_t>(j)];
      if (t >= 0 && t < static_cast<int>(r.dictionary.size()))
        fit.coef[j] *= scale(r.dictionary[static_cast<std::size_t>(t)], s);
    }
}

void scale_effects(std::vector<Effect>& effects, const Scales& s) {
  for (auto& e : effects) e = scale_effect(e, s, +1);
}

void scale_report(Report& r, const Scales& s) {
  const double acceleration = s.length / (s.time * s.time);
  r.residuals.rms *= acceleration;
  scale_path(r.drift_selection, drift_coefficient_scale, s);
  scale_path(r.diffusion_selection, diffusion_coefficient_scale, s);
  scale_effects(r.effect_params, s);
  if (r.profile) {
    scale_effects(r.profile->effects, s);
    for (auto& round : r.profile->rounds) scale_effects(round.effects, s);
    for (auto& c : r.profile->search) {
      for (auto& line : c.spectral_lines) line.frequency /= s.time;
      if (c.scan_step) *c.scan_step /= s.time;
      if (c.lambda_grid) (*c.lambda_grid)[0] /= s.time, (*c.lambda_grid)[1] /= s.time;
    }
  }
  if (r.colored) {
    const double rate = acceleration * acceleration * s.time;
    for (auto& round : r.colored->rounds) round.tau *= s.time, round.intensity *= rate;
    r.colored->lag_lo_time *= s.time;
    r.colored->lag_hi_time *= s.time;
    r.colored->eta_variance_in_residual *= acceleration * acceleration;
    r.colored->residual_variance *= acceleration * acceleration;
  }
}

}  // namespace

Options options_in_internal_units(const Options& options, const Scales& s, std::vector<double>& force) {
  Options o = options;
  for (auto& e : o.effects) e = scale_effect(e, s, -1);
  for (auto* terms : {&o.drift_library, &o.diffusion_library, &o.keep_drift, &o.keep_diffusion})
    *terms = to_internal(std::move(*terms), s);
  if (options.known_force) {
    const double acceleration = s.length / (s.time * s.time);
    force.resize(options.known_force->size());
    for (std::size_t i = 0; i < force.size(); ++i) force[i] = (*options.known_force)[i] / acceleration;
    o.known_force = &force;
  }
  return o;
}

Result result_in_physical_units(Result internal, const Scales& s) {
  // the estimator's reason names the grid step the values lie on: in the data's length unit
  std::string& why = internal.report.estimator.reason;
  const std::string lead(kGridStepLead);
  for (std::size_t at = why.find(lead); at != std::string::npos; at = why.find(lead, at + lead.size())) {
    const char* number = why.c_str() + at + lead.size();
    char* end = nullptr;
    const double q = std::strtod(number, &end);
    if (end == number) continue;
    const std::string to = grid_step_text(q * s.length);
    why.replace(at, lead.size() + static_cast<std::size_t>(end - number), to);
  }
  internal.model = to_physical(internal.model, s);
  scale_report(internal.report, s);
  return internal;
}

void require_finite_standard_errors(const Model& model) {
  auto check = [](const std::map<std::string, double>& errors, const char* where) {
    for (const auto& [name, se] : errors)
      if (!std::isfinite(se))
        throw Error(std::string("identify: the standard error of ") + where + "[" + name +
                    "] is not finite: its estimated variance is not positive (the score covariance "
                    "of the fit is singular — too few batches for the terms, or a term that does "
                    "not vary in the data); remove the term or give more data");
  };
  check(model.drift_stderr, "drift");
  check(model.diffusion_stderr, "diffusion");
  for (const auto& e : model.effects)
    for (const auto& [name, se] : e.stderr_)
      if (!std::isfinite(se))
        throw Error("identify: the standard error of " + e.name() + "." + name +
                    " is not finite (its estimated variance is not positive)");
  if (!model.covariance.empty())
    if (auto why = model.covariance.invalid_reason(); !why.empty())
      throw Error("identify: the covariance of the estimates is not valid: " + why);
}

}  // namespace vehs::identify::detail
