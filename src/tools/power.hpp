#pragma once
// Mean harvested power in watts from the stationary E[Y²] (the velocity variance, in the data's
// units), when the units of the data are SI-convertible and the user gives the harvester's
// electrical constants (config key `harvester`). Otherwise the power is only proportional to
// E[Y²], as in the seed paper.
#include <string>

#include <nlohmann/json.hpp>

#include "tools/config.hpp"

namespace vehs::tools {

/// The --help entry of the `harvester` key.
KeySpec harvester_key();
/// The checked `harvester` block of a config (an empty object when absent).
nlohmann::ordered_json harvester_block(const Config& c);

/// Metres per unit of length ("m", "mm", "um", "µm", "cm") or seconds per unit of time ("s",
/// "ms", "us", "µs", "min"); NaN for any other text.
double si_length(const std::string& unit);
double si_time(const std::string& unit);

struct MeanPower {
  bool available = false;
  double watts = 0.0;
  std::string formula;  ///< how it was computed, or why it was not
};

/// P = c_e·E[v²] with v in m/s: c_e = electrical_damping [N s/m], or mass [kg] ×
/// electrical_damping_rate [1/s], or coupling² [N/A]² · R_load / (R_load + R_coil)² (power in
/// the load of an electromagnetic harvester without inductance).
MeanPower mean_power(double eyy, const nlohmann::json& units, const nlohmann::json& harvester);

}  // namespace vehs::tools
