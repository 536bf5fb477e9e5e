#include "tools/refit_config.hpp"

#include <filesystem>

#include "tools/diagnosis_file.hpp"
#include "tools/measurement_config.hpp"

namespace vehs::tools {

namespace fs = std::filesystem;

std::string refit_config_path(const Config& c, const std::string& report_folder) {
  return c.has("refit") ? c.path("refit") : (fs::path(report_folder) / "refit.json").string();
}

nlohmann::ordered_json refit_identify_config(const Config& c, const diagnose::Result& r, const Model& model,
                                             const std::string& path, const nlohmann::ordered_json& units) {
  nlohmann::ordered_json keys = refit_config(r, model);
  if (keys.is_null()) return keys;
  nlohmann::ordered_json out;
  for (const std::string& k : measurement_file_keys())  // the data as the diagnosis read them
    if (c.has(k)) out[k] = c.raw(k);
  if (!units.empty() && units_block(c).empty()) out["units"] = units;  // from the model file
  out["output"] = (fs::path(path).parent_path() / "refit_model.json").string();
  for (auto it = keys.begin(); it != keys.end(); ++it) out[it.key()] = it.value();
  return out;
}

}  // namespace vehs::tools
