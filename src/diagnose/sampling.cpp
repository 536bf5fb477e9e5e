// The sampling side of a diagnosis: what the model's fit says about its data, the data's own
// sampling diagnosis, and the lens chosen from them.
#include <algorithm>
#include <cmath>
#include <exception>

#include "comparison.hpp"
#include "vehs/core/record_phases.hpp"
#include "unit_math.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::diagnose::detail {

namespace {

/// identify's sampling diagnosis on the first samples of every record.
struct Pilot {
  bool ok = false;
  SamplingVerdict verdict = SamplingVerdict::Unknown;
  Estimator estimator = Estimator::Auto;
  std::string error;
  int stride = 1;
  double sensor_noise_sd = 0.0;
};
Pilot sampling_pilot(const Model& model, const Dataset& data) {
  Pilot p;
  const std::size_t cap = std::max<std::size_t>(4000, 600000 / data.records.size());
  const Dataset sub = leading_samples(data, [&](std::size_t, const Record&, std::size_t) { return cap; });
  identify::Options o;
  o.drift_library = terms_of(model.drift);
  o.diffusion_library = terms_of(model.diffusion);
  o.sparsity = identify::Sparsity::None;
  o.folds = 1;
  o.estimator = Estimator::Auto;
  try {
    const FitInfo fit = *identify::identify(sub, o).model.fit;
    p.ok = true;
    p.verdict = fit.sampling.verdict;
    p.estimator = fit.estimator;
    p.stride = fit.stride;
    p.sensor_noise_sd = fit.sampling.sensor_noise_sd;
  } catch (const std::exception& e) {
    p.error = e.what();
  }
  return p;
}

/// The sampling diagnosis for a model WITH dynamic effects, from the model's own one-step
/// residuals. identify's pilot fits only the model's terms, so the forces of stops, forcing or a
/// hidden state stay in its residuals and their memory reads as sensor noise. Here the residuals
/// e = â − b2 (ULI kinematics at stride 1, b2 including the explicit forces) are used, with
/// identify's sampling_rule (lag 3 as the reference for what a slowly varying force leaves).
Pilot model_sampling_pilot(const Model& model, const Dataset& data) {
  Pilot p;
  Lens L;
  L.kinematics = Kinematics::Central;
  L.stride = 1;
  L.dt = data.common_dt();
  const ModelLens ml(model, L);
  const std::size_t cap = std::max<std::size_t>(4000, 600000 / std::max<std::size_t>(1, data.records.size()));
  double c[4] = {0, 0, 0, 0};
  std::vector<double> e;
  const std::vector<double> origin = forcing_time_origins(model, data, "diagnose", true);
  for (std::size_t j = 0; j < data.records.size(); ++j) {
    const Record& r = data.records[j];
    const std::size_t n = std::min(r.size, cap);
    if (n < 16) continue;
    const double* x = data.x_of(r);
    const double* u = data.has_u() ? data.u_of(r) : nullptr;
    e.clear();
    for (std::size_t i = L.lead(); i + L.trail() < n; ++i) {
      double xi, v, a;
      L.at(x, i, xi, v, a);
      e.push_back(a - ml.b2(xi, v, u ? u[i] : 0.0, origin[j] + static_cast<double>(i) * L.dt));
    }
    for (int l = 0; l < 4; ++l)
      for (std::size_t i = 0; i + static_cast<std::size_t>(l) < e.size(); ++i) c[l] += e[i] * e[i + static_cast<std::size_t>(l)];
  }
  if (!(c[0] > 0.0) || !std::isfinite(c[0])) {
    p.error = "no usable rows for the sampling diagnosis";
    return p;
  }
  double rows = 0.0;
  for (const auto& r : data.records) rows += static_cast<double>(L.rows(std::min(r.size, cap)));
  const identify::SamplingRule rule = identify::sampling_rule(c[1] / c[0], c[2] / c[0], c[3] / c[0], rows);
  p.ok = true;
  p.verdict = rule.verdict;
  p.estimator = rule.noisy ? Estimator::Noisy : rule.continuous ? Estimator::Uli : Estimator::Forward;
  p.stride = 1;
  const double h = L.h();
  p.sensor_noise_sd = rule.noisy ? std::sqrt(rule.noise_share * (c[0] / rows) * h * h * h * h / 6.0) : 0.0;
  return p;
}
/// The lens: the requested kinematics, else central at stride 1 for a likelihood fit, else the
/// model fit's estimator and stride, else the data's
/// sampling diagnosis; sensor noise from the options, the model's measurement noise (a likelihood
/// fit), the moment fit's estimate or the diagnosis.
Lens choose_lens(const Options& opt, const FitInfo& fit, const Pilot& pilot, double dt) {
  Lens lens;
  lens.dt = dt;
  bool forward = false;
  int stride = 1;
  if (opt.lens == LensChoice::Forward) {
    forward = true;
  } else if (opt.lens == LensChoice::Central) {
    stride = fit.stride >= 1 ? fit.stride : (pilot.ok ? pilot.stride : 1);
  } else if (fit.likelihood) {
    stride = 1;  // a continuous-time model: central kinematics at the recorded step
  } else if (fit.estimator != Estimator::Auto) {
    forward = !uses_central_kinematics(fit.estimator);
    stride = fit.stride >= 1 ? fit.stride : 1;
  } else if (pilot.ok) {
    forward = !uses_central_kinematics(pilot.estimator);
    stride = pilot.stride;
  }
  if (opt.stride > 0) stride = opt.stride;
  lens.kinematics = forward ? Kinematics::Forward : Kinematics::Central;
  lens.stride = forward ? 1 : std::max(stride, 1);
  if (opt.sensor_noise >= 0.0)
    lens.sensor_noise_sd = opt.sensor_noise;
  else if (fit.likelihood)  // the model's own measurement noise (0: none; the moment pilot's reading is not the model's)
    lens.sensor_noise_sd = fit.likelihood->measurement_sd;
  else if (fit.sampling.sensor_noise_sd > 0.0)
    lens.sensor_noise_sd = fit.sampling.sensor_noise_sd;
  else if (pilot.ok && pilot.verdict == SamplingVerdict::Noisy)
    lens.sensor_noise_sd = pilot.sensor_noise_sd;
  if (auto why = lens.invalid_reason(); !why.empty()) throw Error("diagnose: lens: " + why);
  return lens;
}

}  // namespace

SamplingChoice choose_sampling_and_lens(const Model& model, const Dataset& data, const Options& opt, Result& res) {
  const double dt = data.common_dt();
  SamplingInfo& si = res.sampling;
  si.data_dt = dt;
  // ---- what the model says about the data it was fitted to
  const FitInfo fit = model.fit.value_or(FitInfo{});
  si.model_dt = fit.sampling.dt;
  si.model_verdict = fit.sampling.verdict;
  si.model_estimator = fit.estimator;
  // A likelihood fit (vehs/likelihood/observed_model.hpp) is a continuous-time SDE observed at
  // the sampling instants with white measurement noise: its twins are simulated so at any Δt
  // (the moment pilot's reading, kept in the file, can be wrong at coarse sampling), and its
  // coefficients do not depend on the sampling interval.
  if (fit.likelihood)
    si.model_verdict = fit.likelihood->measurement_sd > 0.0 ? SamplingVerdict::Noisy : SamplingVerdict::ContinuousTime;
  if (opt.check_model_sampling && !fit.likelihood && si.model_dt > 0.0 && std::abs(si.model_dt - dt) > 1e-6 * dt)
    throw Error("the model was identified from data sampled at dt = " + fmt(si.model_dt, 8) +
                " (its 'sampling.dt') but these data are sampled at dt = " + fmt(dt, 8) +
                ": coefficients fitted to a discrete scheme depend on the interval; diagnose data "
                "sampled like the model's, or set check_model_sampling to false");
  // ---- the data's own sampling diagnosis (identify's pilot, model terms as the library)
  const Pilot pilot = model.has_dynamic_effects() ? model_sampling_pilot(model, data) : sampling_pilot(model, data);
  si.data_verdict = pilot.ok ? pilot.verdict : SamplingVerdict::Unknown;
  const SamplingVerdict assumed =
      si.model_verdict == SamplingVerdict::Unknown ? SamplingVerdict::ContinuousTime : si.model_verdict;
  if (!pilot.ok)
    res.warnings.push_back("the sampling diagnosis of the data failed (" + pilot.error + "); assuming " +
                           enum_to_string(kSamplingVerdictNames, assumed) + " data");
  if (pilot.ok && si.model_verdict != SamplingVerdict::Unknown && si.model_verdict != pilot.verdict)
    res.warnings.push_back("the model file says its data were '" + enum_to_string(kSamplingVerdictNames, si.model_verdict) +
                           "' but these data look '" + enum_to_string(kSamplingVerdictNames, pilot.verdict) + "'");
  SamplingChoice choice;
  choice.verdict = pilot.ok ? pilot.verdict : assumed;
  if (fit.likelihood) choice.verdict = si.model_verdict;  // the likelihood's model says how it was observed
  if (opt.sensor_noise > 0.0) choice.verdict = SamplingVerdict::Noisy;  // the user says so
  choice.lens = choose_lens(opt, fit, pilot, dt);
  res.lens = choice.lens;
  si.sensor_noise_sd = choice.lens.sensor_noise_sd;
  return choice;
}

}  // namespace vehs::diagnose::detail
