#include "vehs/io/parameter_units.hpp"

#include <utility>

namespace vehs {

namespace {

std::string unit_name(const nlohmann::json& units, const char* key, const char* fallback) {
  if (units.is_object() && units.contains(key) && units[key].is_string()) return units[key].get<std::string>();
  return fallback;
}

bool compound(const std::string& name) { return name.find_first_of("/ *") != std::string::npos; }

/// name^power; a compound name ("m/s^2") is parenthesised when raised to a power or combined with
/// other factors, so that it reads as one unit.
std::string factor(const std::string& name, int power, bool alone) {
  const bool wrap = compound(name) && (power != 1 || !alone);
  const std::string base = wrap ? "(" + name + ")" : name;
  return power == 1 ? base : base + "^" + std::to_string(power);
}

std::string joined(const std::vector<std::string>& factors) {
  std::string s;
  for (const auto& f : factors) s += (s.empty() ? "" : " ") + f;
  return s;
}

}  // namespace

std::string unit_text(const Dimension& d, const nlohmann::json& units) {
  const std::string input = unit_name(units, "input", "input");
  if (d.input != 0 && compound(input)) {  // a compound input unit (m/s^2) is divided or multiplied whole
    const std::string rest = unit_text({d.length, d.time, 0}, units);
    const std::string in = factor(input, std::abs(d.input), false);
    const std::string r = compound(rest) ? "(" + rest + ")" : rest;
    if (d.input < 0) return r + "/" + in;
    return rest == "1" ? factor(input, d.input, true) : in + " " + r;
  }
  const std::pair<std::string, int> parts[] = {{unit_name(units, "length", "length"), d.length},
                                               {input, d.input},
                                               {unit_name(units, "time", "time"), d.time}};
  int factors = 0;
  for (const auto& part : parts) factors += part.second != 0;
  std::vector<std::string> num, den;
  for (const auto& [name, power] : parts) {
    if (power > 0) num.push_back(factor(name, power, factors == 1));
    if (power < 0) den.push_back(factor(name, -power, false));  // 1/(m/s^2): wrapped below a bar
  }
  if (den.empty()) return num.empty() ? "1" : joined(num);
  const std::string below = den.size() > 1 ? "(" + joined(den) + ")" : joined(den);
  return (num.empty() ? "1" : joined(num)) + "/" + below;
}

std::string parameter_unit(const std::string& name, const nlohmann::json& units) {
  if (name == "harmonic_forcing.phase") return "rad";
  return unit_text(parameter_dimension(name), units);
}

std::vector<ParameterRow> parameter_rows(const Model& m, const nlohmann::json& units) {
  std::vector<ParameterRow> rows;
  for (auto& p : physical_parameters(m)) {
    std::string unit = parameter_unit(p.name, units);
    rows.push_back({std::move(p), std::move(unit)});
  }
  return rows;
}

nlohmann::json units_of(const nlohmann::ordered_json& sections) {
  if (sections.is_object() && sections.contains("units") && sections["units"].is_object())
    return nlohmann::json(sections["units"]);
  return nlohmann::json::object();
}

}  // namespace vehs
