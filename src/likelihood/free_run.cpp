#include "vehs/likelihood/free_run.hpp"

#include <cmath>
#include <string>

#include <Eigen/Core>

#include "vehs/core/error.hpp"
#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"
#include "vehs/likelihood/detail/input_path.hpp"
#include "vehs/likelihood/ode.hpp"

namespace vehs::likelihood {

namespace {

/// The noise-free vector field of the state (x, y, v, η) at a point.
struct VectorField {
  const Model& m;
  effects::ImpactStop<double> stop;
  effects::HarmonicForcing<double> forcing;
  double lambda = 0,
         coupling = 0, tau = 1;
  bool impact = false, harmonic = false, electro = false, colored = false;
  double t0 = 0, inv_dt = 1;
  detail::InputCubic u{};

  explicit VectorField(const Model& model, const FreeRunOptions& o) : m(model) {
    for (const auto& e : m.effects) {
      switch (e.id) {
        case EffectId::ImpactStop:
          impact = true;
          stop = effects::from_effect<effects::ImpactStop>(e);
          break;
        case EffectId::HarmonicForcing:
          harmonic = true;
          forcing = effects::from_effect<effects::HarmonicForcing>(e);
          if (o.phase) forcing.phase = *o.phase;
          break;
        case EffectId::ElectromechanicalCoupling:
          electro = true;
          lambda = e.param("lambda");
          coupling = e.param("coupling");
          break;
        case EffectId::ColoredNoise:
          colored = true;
          tau = e.param("tau");
          break;
        default: break;
      }
    }
  }
  bool operator()(double t, const Eigen::Vector4d& s, Eigen::Vector4d& ds) const {
    double b = m.b2(s[0], s[1], detail::eval_cubic(u, (t - t0) * inv_dt));
    if (impact) b += stop.force(s[0]);
    if (harmonic) b += forcing.force(t);
    if (electro) b -= coupling * s[2];
    if (colored) b += s[3];
    ds[0] = s[1];
    ds[1] = b;
    ds[2] = electro ? s[1] - lambda * s[2] : 0.0;
    ds[3] = colored ? -s[3] / tau : 0.0;
    return std::isfinite(b);
  }
};

}  // namespace

std::vector<double> free_run(const Model& model, const InitialState& initial,
                             const std::vector<double>& u, double dt, std::size_t samples,
                             const FreeRunOptions& options) {
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("free run: the sampling interval must be > 0");
  if (options.substeps < 1) throw Error("free run: substeps must be >= 1");
  const bool drive = model.uses_drive();
  if (drive && u.size() < samples)
    throw Error("free run: the input has " + std::to_string(u.size()) + " samples for " +
                std::to_string(samples) + " samples to simulate");
  VectorField f(model, options);
  Eigen::Vector4d s(initial.x, initial.y, initial.v, initial.eta);
  std::vector<double> x(samples);
  if (samples == 0) return x;
  x[0] = s[0];
  for (std::size_t k = 1; k < samples; ++k) {
    const double t = options.t0 + double(k - 1) * dt;
    f.t0 = t;
    f.inv_dt = 1.0 / dt;
    f.u = drive ? detail::input_cubic(u.data(), u.size(), k - 1, options.input) : detail::InputCubic{};
    if (!rk4_propagate(f, t, dt, options.substeps, s) || !s.allFinite() ||
        std::abs(s[0]) > options.divergence_bound || std::abs(s[1]) > options.divergence_bound)
      throw Error("free run: the simulation diverged at sample " + std::to_string(k) +
                  " (|x| or |y| beyond " + std::to_string(options.divergence_bound) + ")");
    x[k] = s[0];
  }
  return x;
}

Validation validate_free_run(const Model& model, const std::vector<double>& x,
                             const std::vector<double>& u, double dt, std::size_t skip,
                             const FreeRunOptions& options,
                             const std::optional<InitialState>& initial) {
  if (x.size() < 3 || skip >= x.size())
    throw Error("validation: the segment has " + std::to_string(x.size()) +
                " samples; it needs at least 3 and more than the " + std::to_string(skip) +
                " skipped");
  Validation v;
  v.skip = skip;
  v.measured = x;
  if (initial) {
    v.initial = *initial;
  } else {
    v.initial.x = x[0];
    v.initial.y = (-3.0 * x[0] + 4.0 * x[1] - x[2]) / (2.0 * dt);
  }
  v.simulated = free_run(model, v.initial, u, dt, x.size(), options);
  double se = 0.0, ss = 0.0;
  for (std::size_t k = skip; k < x.size(); ++k) {
    const double d = v.simulated[k] - x[k];
    se += d * d;
    ss += x[k] * x[k];
  }
  const double n = double(x.size() - skip);
  v.rmse = std::sqrt(se / n);
  v.measured_rms = std::sqrt(ss / n);
  return v;
}

}  // namespace vehs::likelihood
