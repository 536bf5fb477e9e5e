#pragma once
// The parameter table that identify-vehs and diagnose-vehs print: each parameter by its physical
// name (vehs/core/parameters.hpp), its value, standard error, unit (vehs/io/parameter_units.hpp,
// from the data's `units` block) and the coefficient it is read from.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"

namespace vehs::tools {

/// The table, one line per parameter, with a header line; `indent` prefixes every line.
std::string parameter_table(const Model& m, const nlohmann::json& units, const std::string& indent = "");

}  // namespace vehs::tools
