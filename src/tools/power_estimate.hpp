#pragma once
// Mean power with a standard error from a Monte Carlo run of a model (driven or not): the
// simulation's error (batch means or the spread of independent records) and, on request, the
// error of the fitted parameters carried through by the delta method (central differences at
// ±1 SE with common random numbers).
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/core/statistics.hpp"

namespace vehs::tools {

/// E[Y^2] with its Monte Carlo standard error from a run of `model` (same seed and drive each call).
using RunEyy = std::function<vehs::Estimate(const Model& model)>;

/// The model's parameters with a positive variance in its covariance (what parameter
/// propagation perturbs); throws a one-line vehs::Error when the model has no covariance.
std::size_t uncertain_parameters(const Model& model, const std::string& where);

/// The "mean_power" section of simulate-vehs's statistics: E[Y^2] and the power in W (null
/// without harvester constants or SI units) with their standard errors; with `parameters`,
/// 2 runs per uncertain parameter more.
nlohmann::ordered_json power_section(const Model& model, const vehs::Estimate& eyy, const nlohmann::json& units,
                                     const nlohmann::json& harvester, bool parameters, const RunEyy& run,
                                     const std::string& error_method);

}  // namespace vehs::tools
