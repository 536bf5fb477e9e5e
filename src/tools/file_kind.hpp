#pragma once
// What a JSON file given to a tool is, from the keys its writer always puts at the top level
// (docs/outputs.md, docs/model-file.md): so that a model file given as a statistics file, or
// fpk-stationary's output given as Monte Carlo statistics, is refused with both kinds named.
#include <string>

#include <nlohmann/json.hpp>

namespace vehs::tools {

enum class FileKind {
  Model,              ///< "drift" / "diffusion" (identify-vehs, or by hand)
  FpkResult,          ///< "solve" and "boundary_mass" (fpk-stationary's output)
  MonteCarloStatistics,  ///< "stderr" and "simulation" (simulate-vehs's statistics.output)
  Other,
};

FileKind file_kind(const nlohmann::json& j);

/// "a model file", "fpk-stationary's output", ...: for "names x.json, <description>".
std::string describe(FileKind kind);

}  // namespace vehs::tools
