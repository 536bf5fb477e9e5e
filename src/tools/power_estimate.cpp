#include "tools/power_estimate.hpp"

#include <cmath>

#include "tools/power.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs::tools {

namespace {

/// (E+ - E-)/2 for each perturbed parameter (index into the covariance), E± at θ ± SE.
struct Sensitivity {
  std::size_t index;
  double half_difference;
};

Sensitivity sensitivity(const Model& model, std::size_t i, const RunEyy& run) {
  const ParameterCovariance& cov = model.covariance;
  const std::string& name = cov.names[i];
  const double se = std::sqrt(cov(i, i)), value = get_parameter(model, name);
  Model up = model, down = model;
  set_parameter(up, name, value + se);
  set_parameter(down, name, value - se);
  try {
    return {i, 0.5 * (run(up).value - run(down).value)};
  } catch (const Error& e) {
    throw Error("parameter uncertainty: the model with " + name + " moved by 1 SE fails: " + e.what());
  }
}

}  // namespace

std::size_t uncertain_parameters(const Model& model, const std::string& where) {
  if (model.covariance.empty())
    throw Error(where + ": the model has no covariance (a fitted model file has one): parameter uncertainty "
                        "cannot be propagated");
  std::size_t n = 0;
  for (std::size_t i = 0; i < model.covariance.size(); ++i) n += model.covariance(i, i) > 0.0;
  return n;
}

nlohmann::ordered_json power_section(const Model& model, const vehs::Estimate& eyy, const nlohmann::json& units,
                                     const nlohmann::json& harvester, bool parameters, const RunEyy& run,
                                     const std::string& error_method) {
  double var_param = 0.0;
  if (parameters) {
    std::vector<Sensitivity> d;
    const ParameterCovariance& cov = model.covariance;
    for (std::size_t i = 0; i < cov.size(); ++i)
      if (cov(i, i) > 0.0) d.push_back(sensitivity(model, i, run));
    for (const auto& a : d)
      for (const auto& b : d) {
        const double rho = cov(a.index, b.index) / std::sqrt(cov(a.index, a.index) * cov(b.index, b.index));
        var_param += a.half_difference * b.half_difference * rho;
      }
    var_param = std::max(var_param, 0.0);
  }
  const double se_mc = eyy.stderr_, se_param = std::sqrt(var_param);
  const double se = std::sqrt(se_mc * se_mc + var_param);
  nlohmann::ordered_json j;
  j["E[Y^2]"] = eyy.value;
  j["E[Y^2]_stderr"] = se;
  const MeanPower p = mean_power(eyy.value, units, harvester);
  const double watts_per_eyy = p.available && eyy.value != 0.0 ? p.watts / eyy.value : 0.0;
  const auto watts = [&](double v) { return p.available ? nlohmann::json(watts_per_eyy * v) : nlohmann::json(nullptr); };
  j["watts"] = p.available ? nlohmann::json(p.watts) : nlohmann::json(nullptr);
  j["stderr"] = watts(se);
  j["monte_carlo_stderr"] = watts(se_mc);
  j["parameter_stderr"] = parameters ? watts(se_param) : nlohmann::json(nullptr);
  j["how"] = p.formula;
  j["error_method"] = error_method + (parameters ? " + parameter covariance (delta method, ±1 SE, common random numbers)"
                                                 : " (Monte Carlo only; parameter errors not included)");
  return j;
}

}  // namespace vehs::tools
