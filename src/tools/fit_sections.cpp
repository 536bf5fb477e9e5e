// The model file's sections that describe vehs::fit's steps (JSON only at the file boundary).
#include "tools/fit_sections.hpp"

#include <cmath>

namespace vehs::tools {

/// Whether the likelihood refined the moment fit, and why (vehs/likelihood/adequacy.hpp).
nlohmann::ordered_json adequacy_json(const Refinement& f) {
  nlohmann::ordered_json j;
  if (std::isfinite(f.adequacy.omega_dt)) j["omega_dt"] = f.adequacy.omega_dt;
  if (std::isfinite(f.adequacy.increments_omega_dt)) j["increments_omega_dt"] = f.adequacy.increments_omega_dt;
  if (std::isfinite(f.adequacy.stiffness_omega_dt)) j["stiffness_omega_dt"] = f.adequacy.stiffness_omega_dt;
  if (f.adequacy.recorded_input && std::isfinite(f.adequacy.input_omega_dt))
    j["input_omega_dt"] = f.adequacy.input_omega_dt;
  j["vouched"] = f.adequacy.vouched;
  j["likelihood"] = f.result ? "used" : !f.failure.empty() ? "failed" : "not used";
  j["reason"] = f.adequacy.reason;
  if (!f.failure.empty()) j["failure"] = f.failure;
  if (!f.input_reason.empty()) j["input"] = f.input_reason;
  if (!f.warnings.empty()) j["warnings"] = f.warnings;
  return j;
}

nlohmann::ordered_json likelihood_starts_json(const std::vector<LikelihoodStart>& starts) {
  nlohmann::ordered_json j = nlohmann::ordered_json::array();
  for (const LikelihoodStart& s : starts) {
    nlohmann::ordered_json e;
    e["start"] = s.name;
    if (s.measurement_sd > 0.0) e["measurement_sd_start"] = s.measurement_sd;
    if (std::isfinite(s.log_likelihood)) e["log_likelihood"] = s.log_likelihood, e["seconds"] = s.seconds;
    e["status"] = s.status;
    j.push_back(e);
  }
  return j;
}


nlohmann::ordered_json recorded_input_json(const RecordedInput& input) {
  if (input.column.empty()) return nullptr;
  return {{"column", input.column},
          {"in_drift_library", input.in_drift_library},
          {"added", input.added},
          {"why", input.why}};
}

}  // namespace vehs::tools
