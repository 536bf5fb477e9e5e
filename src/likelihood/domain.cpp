#include "vehs/likelihood/detail/domain.hpp"

#include <cmath>
#include <sstream>

#include "vehs/core/error.hpp"

namespace vehs::likelihood::detail {

namespace {

/// harmonic_forcing with a negative amplitude → the positive amplitude at phase + π.
void flip_negative_amplitude(Result& r) {
  Model& m = r.model.model;
  for (Effect& e : m.effects) {
    if (e.id != EffectId::HarmonicForcing) continue;
    auto amp = e.params.find("amplitude");
    if (amp == e.params.end() || !(amp->second < 0.0)) continue;
    amp->second = -amp->second;
    e.params["phase"] = std::remainder(e.params["phase"] + M_PI, 2.0 * M_PI);
    for (double& ph : r.model.record_phases) ph = std::remainder(ph + M_PI, 2.0 * M_PI);
    for (std::size_t i = 0; i < r.parameters.size(); ++i) {
      const ParameterInfo& p = r.parameters[i];
      if (p.name == "harmonic_forcing.amplitude") {
        r.values[i] = -r.values[i];
        r.covariance.row(Eigen::Index(i)) *= -1.0;
        r.covariance.col(Eigen::Index(i)) *= -1.0;
      } else if (p.name == "harmonic_forcing.phase" || p.kind == ParameterKind::RecordPhase) {
        r.values[i] = std::remainder(r.values[i] + M_PI, 2.0 * M_PI);
      }
    }
  }
}

}  // namespace

void respect_domain(Result& r) {
  flip_negative_amplitude(r);
  for (const Effect& e : r.model.model.effects) {
    const std::string why = effect_domain_violation(e);
    if (why.empty()) continue;
    std::ostringstream os;
    os << "likelihood: the maximum-likelihood estimate " << why;
    for (const auto& [key, se] : e.stderr_)
      if (why.rfind(e.name() + "." + key + " ", 0) == 0) os << " (standard error " << se << ")";
    os << ": the data do not support " << e.name()
       << " as the catalogue defines it, and a model file cannot hold the estimate; fit without it";
    throw Error(os.str());
  }
  validate_model(r.model.model, "likelihood: the fitted model");
}

}  // namespace vehs::likelihood::detail
