#pragma once
// Every parameter of a model with its unit: the one rule behind the parameter tables of
// identify-vehs, diagnose-vehs and vehs-compare and Python's vehs.Model.parameters(). A unit is
// the parameter's dimension (vehs/core/parameters.hpp: powers of length, time and input) written
// in the names of the data's `units` block ({"length": "mm", "time": "s", "input": "V"}, the model
// file's `units` section); a name the block lacks is written as the quantity ("length", "time",
// "input"), so a model without units still shows what a parameter's unit is made of.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/core/parameters.hpp"

namespace vehs {

/// A dimension in the units block's names: "mm/s^2", "1/(mm^2 s^2)", "1" when dimensionless. A
/// compound input unit divides or multiplies the rest whole: "(mm/s^2)/(m/s^2)" for drift[u]
/// with a base acceleration in m/s^2 ("mm/(V s^2)" with volts).
std::string unit_text(const Dimension& d, const nlohmann::json& units);

/// The unit of a parameter named as in parameters.hpp ("rad" for harmonic_forcing.phase).
std::string parameter_unit(const std::string& name, const nlohmann::json& units);

/// A parameter of a model (physical_parameters) with its unit.
struct ParameterRow {
  PhysicalParameter parameter;
  std::string unit;
};

/// physical_parameters(m) in their order, each with parameter_unit(name, units).
std::vector<ParameterRow> parameter_rows(const Model& m, const nlohmann::json& units);

/// The model file's `units` section (an empty object when it has none).
nlohmann::json units_of(const nlohmann::ordered_json& sections);

}  // namespace vehs
