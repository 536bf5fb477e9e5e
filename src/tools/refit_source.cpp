#include "tools/refit_source.hpp"

#include <filesystem>

#include "vehs/core/error.hpp"
#include "vehs/io/json_file.hpp"

namespace vehs::tools {

namespace fs = std::filesystem;

namespace {

std::string from_diagnosis(const nlohmann::json& j, const std::string& file) {
  const auto& named = j.contains("refit_file") ? j["refit_file"] : nlohmann::json();
  if (named.is_null())
    throw Error(file + ": the diagnosis recommends no refit (verdict " + json_excerpt(j["verdict"]) +
                ", refit_config null): there is nothing to run");
  if (!named.is_string()) throw Error(file + ": 'refit_file' must be a path (got " + json_excerpt(named) + ")");
  const fs::path written = named.get<std::string>();
  if (fs::exists(written)) return written.string();
  const fs::path beside = fs::path(file).parent_path() / written.filename();
  if (fs::exists(beside)) return beside.string();
  throw Error(file + ": its refit config " + written.string() + " does not exist (run diagnose-vehs again)");
}

}  // namespace

std::string refit_config_for(const std::string& file) {
  const nlohmann::json j = read_json_file(file, "diagnosis file or refit config");
  if (!j.is_object()) throw Error(file + ": not a diagnosis file or refit config (a JSON object)");
  if (j.contains("verdict")) return from_diagnosis(j, file);
  if (j.contains("data") || j.contains("measurement")) return file;
  throw Error(file + ": neither a diagnosis file (no 'verdict') nor an identify-vehs config (no 'data')");
}

}  // namespace vehs::tools
