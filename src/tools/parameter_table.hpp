#pragma once
// The parameter table that identify-vehs and diagnose-vehs print: each parameter by its physical
// name (vehs/core/parameters.hpp), its value, standard error, unit (from the data's `units`
// block) and the coefficient it is read from.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs::tools {

/// A dimension in the units block's names ("mm", "s", "V"; "length", "time", "input" when a
/// name is absent): "mm/s^2", "1/(mm^2 s^2)", "1" when dimensionless.
std::string unit_text(const Dimension& d, const nlohmann::json& units);

/// The unit of a parameter named as in parameters.hpp ("rad" for harmonic_forcing.phase).
std::string parameter_unit(const std::string& name, const nlohmann::json& units);

/// The table, one line per parameter, with a header line; `indent` prefixes every line.
std::string parameter_table(const Model& m, const nlohmann::json& units, const std::string& indent = "");

}  // namespace vehs::tools
