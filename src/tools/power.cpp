#include "tools/power.hpp"

#include <cmath>
#include <limits>

#include "vehs/core/detail/format.hpp"

namespace vehs::tools {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double number(const nlohmann::json& h, const char* key) {
  return h.contains(key) && h[key].is_number() ? h[key].get<double>() : kNaN;
}
}  // namespace

KeySpec harvester_key() {
  return {"harvester", "object",
          "Electrical constants for the mean harvested power in W (needs SI-convertible units in the "
          "model file, e.g. length \"mm\", time \"s\"): {\"electrical_damping\": c_e in N s/m}, or "
          "{\"mass\": kg, \"electrical_damping_rate\": 1/s}, or {\"coupling\": theta in N/A, "
          "\"load_resistance\": ohm, \"coil_resistance\": ohm} (power in the load, inductance "
          "neglected). P = c_e E[Y^2] with Y in m/s. Without it the output gives E[Y^2], to which "
          "the power is proportional.",
          "", true};
}

nlohmann::ordered_json harvester_block(const Config& c) {
  nlohmann::ordered_json h = nlohmann::ordered_json::object();
  if (!c.has("harvester")) return h;
  const Config k = c.object("harvester", {"electrical_damping", "mass", "electrical_damping_rate", "coupling",
                                          "load_resistance", "coil_resistance"});
  for (const char* key : {"electrical_damping", "mass", "electrical_damping_rate", "coupling", "load_resistance"})
    if (k.has(key)) h[key] = k.positive(key);
  if (k.has("coil_resistance")) h["coil_resistance"] = k.non_negative_or("coil_resistance", 0.0);
  const bool ce = h.contains("electrical_damping"), rate = h.contains("mass") || h.contains("electrical_damping_rate"),
             coil = h.contains("coupling") || h.contains("load_resistance");
  if (ce + rate + coil != 1)
    c.fail("harvester", "give one of: electrical_damping; mass with electrical_damping_rate; coupling with "
                        "load_resistance (and coil_resistance)");
  if (rate && !(h.contains("mass") && h.contains("electrical_damping_rate")))
    c.fail("harvester", "needs both mass and electrical_damping_rate");
  if (coil && !(h.contains("coupling") && h.contains("load_resistance")))
    c.fail("harvester", "needs both coupling and load_resistance");
  return h;
}

double si_length(const std::string& u) {
  if (u == "m") return 1.0;
  if (u == "cm") return 1e-2;
  if (u == "mm") return 1e-3;
  if (u == "um" || u == "µm") return 1e-6;
  return kNaN;
}

double si_time(const std::string& u) {
  if (u == "s") return 1.0;
  if (u == "ms") return 1e-3;
  if (u == "us" || u == "µs") return 1e-6;
  if (u == "min") return 60.0;
  return kNaN;
}

MeanPower mean_power(double eyy, const nlohmann::json& units, const nlohmann::json& h) {
  MeanPower p;
  if (!h.is_object() || h.empty()) {
    p.formula = "no harvester constants given: the mean power is proportional to E[Y^2]";
    return p;
  }
  const std::string L = units.is_object() && units.contains("length") ? units["length"].get<std::string>() : "";
  const std::string T = units.is_object() && units.contains("time") ? units["time"].get<std::string>() : "";
  const double l = si_length(L), t = si_time(T);
  if (!std::isfinite(l) || !std::isfinite(t)) {
    p.formula = "the model's units (length '" + L + "', time '" + T +
                "') are not SI-convertible (m, mm, um, cm; s, ms, us): the mean power is proportional to E[Y^2]";
    return p;
  }
  const double v2 = eyy * (l / t) * (l / t);  // (m/s)^2
  double ce = number(h, "electrical_damping");
  std::string how = "electrical_damping";
  if (!std::isfinite(ce) && h.contains("mass")) {
    ce = number(h, "mass") * number(h, "electrical_damping_rate");
    how = "mass * electrical_damping_rate";
  }
  if (!std::isfinite(ce) && h.contains("coupling")) {
    const double th = number(h, "coupling"), R = number(h, "load_resistance");
    const double Rc = h.contains("coil_resistance") ? number(h, "coil_resistance") : 0.0;
    ce = th * th * R / ((R + Rc) * (R + Rc));
    how = "coupling^2 * load_resistance / (load_resistance + coil_resistance)^2";
  }
  p.available = std::isfinite(ce) && std::isfinite(v2);
  p.watts = ce * v2;
  p.formula = "P = c_e E[Y^2] with c_e = " + how + " = " + vehs::detail::format_number(ce, 6) +
              " N s/m and E[Y^2] = " + vehs::detail::format_number(v2, 6) + " (m/s)^2";
  return p;
}

}  // namespace vehs::tools
