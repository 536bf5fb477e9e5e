#include "vehs/likelihood/detail/record_phase_bias.hpp"

#include <cmath>

namespace vehs::likelihood::detail {

double record_phase_amplitude_factor(const Result& res) {
  if (res.find("harmonic_forcing.amplitude") < 0) return 1.0;
  double inverse_sum = 0.0;
  std::size_t records = 0;
  for (std::size_t i = 0; i < res.parameters.size(); ++i) {
    if (res.parameters[i].kind != ParameterKind::RecordPhase) continue;
    const double var = res.covariance(Eigen::Index(i), Eigen::Index(i));
    if (!(var > 0.0) || !std::isfinite(var)) return 1.0;
    inverse_sum += 1.0 / var;
    ++records;
  }
  if (records == 0) return 1.0;
  const double h = double(records) / inverse_sum;  // harmonic mean of Var(φ̂_r)
  const double f = 1.0 - 0.5 * h;
  return f > 0.5 ? f : 1.0;  // (a phase not determined at all: no first-order correction)
}

double correct_record_phase_bias(Result& res) {
  const double f = record_phase_amplitude_factor(res);
  if (f == 1.0) return f;
  const auto i = std::size_t(res.find("harmonic_forcing.amplitude"));
  res.values[i] *= f;
  res.stderrs[i] *= f;
  res.covariance.row(Eigen::Index(i)) *= f;
  res.covariance.col(Eigen::Index(i)) *= f;
  for (Effect& e : res.model.model.effects)
    if (e.id == EffectId::HarmonicForcing) {
      e.params["amplitude"] = res.values[i];
      if (e.stderr_.count("amplitude")) e.stderr_["amplitude"] = res.stderrs[i];
    }
  return f;
}

}  // namespace vehs::likelihood::detail
