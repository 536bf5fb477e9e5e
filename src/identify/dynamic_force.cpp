// The forces of dynamic effects along a record, as identify and diagnose evaluate them.
#include <cmath>

#include "vehs/effects/from_model.hpp"
#include "vehs/effects/harmonic_forcing.hpp"
#include "vehs/effects/impact_stop.hpp"
#include "vehs/identify/dynamic.hpp"

namespace vehs::identify {

bool is_dynamic(EffectId id) { return !effect_spec(id).term_like; }

bool dynamic_fit_supported(EffectId id) {
  return id == EffectId::HarmonicForcing || id == EffectId::ImpactStop || id == EffectId::ElectromechanicalCoupling ||
         id == EffectId::ColoredNoise;
}

void filtered_velocity(const double* x, std::size_t n, double dt, double lambda, double* v) {
  if (n == 0) return;
  const double z = lambda * dt;
  const double a = std::exp(-z);
  const double g = z > 1e-8 ? -std::expm1(-z) / z : 1.0 - 0.5 * z;
  v[0] = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) v[i + 1] = a * v[i] + g * (x[i + 1] - x[i]);
}

void dynamic_force(const std::vector<Effect>& effects, const Dataset& data, const Record& r,
                   std::vector<double>& out, int tent_k) {
  out.assign(r.size, 0.0);
  const double* x = data.x_of(r);
  std::vector<double> v;
  for (const auto& e : effects) {
    switch (e.id) {
      case EffectId::HarmonicForcing: {
        effects::add_harmonic_forcing_record_force(effects::from_effect<effects::HarmonicForcing>(e), r.t0, r.dt,
                                                   r.size, out.data());
        break;
      }
      case EffectId::ImpactStop: {
        effects::add_impact_stop_record_force(effects::from_effect<effects::ImpactStop>(e), x, r.size, tent_k,
                                              out.data());
        break;
      }
      case EffectId::ElectromechanicalCoupling: {
        v.resize(r.size);
        filtered_velocity(x, r.size, r.dt, e.param("lambda"), v.data());
        const double cpl = e.param("coupling");
        for (std::size_t i = 0; i < r.size; ++i) out[i] -= cpl * v[i];
        break;
      }
      default: break;
    }
  }
}

}  // namespace vehs::identify
