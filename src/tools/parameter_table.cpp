#include "tools/parameter_table.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "vehs/core/detail/format.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/io/parameter_units.hpp"

namespace vehs::tools {

namespace {

std::string g(double v, int digits) { return std::isfinite(v) ? vehs::detail::format_number(v, digits) : "-"; }

}  // namespace

std::string parameter_table(const Model& m, const nlohmann::json& units, const std::string& indent) {
  const auto params = parameter_rows(m, units);
  const std::size_t phases = record_phases_of(m).size();
  struct Row {
    std::string name, value, se, unit, from;
  };
  std::vector<Row> rows = {{"parameter", "value", "stderr", "unit", "from"}};
  for (const auto& [p, unit] : params) {
    Row r{p.name, g(p.value, 6), p.stderr_ ? g(*p.stderr_, 3) : "", unit, ""};
    if (!p.coefficient.empty() && p.coefficient != p.name)
      r.from = (p.sign < 0 ? "-" : "") + std::string(std::abs(p.sign) != 1.0 ? g(std::abs(p.sign), 3) + " " : "") +
               p.coefficient;
    if (phases > 0 && p.name == "harmonic_forcing.phase")  // the file's value is a placeholder
      r.value = "per record", r.se = "(" + std::to_string(phases) + " in likelihood.record_phases)";
    rows.push_back(r);
  }
  std::size_t w[4] = {0, 0, 0, 0};
  for (const auto& r : rows) {
    w[0] = std::max(w[0], r.name.size());
    w[1] = std::max(w[1], r.value.size());
    w[2] = std::max(w[2], r.se.size());
    w[3] = std::max(w[3], r.unit.size());
  }
  auto pad = [](const std::string& s, std::size_t n, bool right) {
    const std::string fill(n > s.size() ? n - s.size() : 0, ' ');
    return right ? fill + s : s + fill;
  };
  std::string out;
  for (const auto& r : rows) {
    std::string line = indent + pad(r.name, w[0], false) + "  " + pad(r.value, w[1], true) + "  " +
                       pad(r.se, w[2], true) + "  " + pad(r.unit, w[3], false) + "  " + r.from;
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line + "\n";
  }
  return out;
}

}  // namespace vehs::tools
