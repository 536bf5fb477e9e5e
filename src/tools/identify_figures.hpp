#pragma once
// identify-vehs's figure of a fitted model over its data: the drift as a force vs x at y = 0 and
// vs y at x = 0, the potential U(x) = −∫ b2(s, 0) ds, and the diffusion a22(x, 0), each with a
// 95 % band from the covariance of the estimates (the standard errors when the model file has no
// covariance) and binned Kramers–Moyal estimates from the data (vehs/identify/binned.hpp).
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs::tools {

/// Writes identify_fit.svg with its CSVs and gnuplot script into `dir`; returns the SVG's path
/// ("" when gnuplot is missing or failed).
std::string identify_figure(const std::string& dir, const Model& model, const Dataset& data,
                            const nlohmann::json& units);

}  // namespace vehs::tools
