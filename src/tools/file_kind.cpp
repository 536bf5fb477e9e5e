#include "tools/file_kind.hpp"

namespace vehs::tools {

FileKind file_kind(const nlohmann::json& j) {
  if (!j.is_object()) return FileKind::Other;
  if (j.contains("solve") && j.contains("boundary_mass")) return FileKind::FpkResult;
  if (j.contains("stderr") && j.contains("simulation")) return FileKind::MonteCarloStatistics;
  if (j.contains("drift") || j.contains("diffusion")) return FileKind::Model;
  return FileKind::Other;
}

std::string describe(FileKind kind) {
  switch (kind) {
    case FileKind::Model: return "a model file";
    case FileKind::FpkResult: return "fpk-stationary's output";
    case FileKind::MonteCarloStatistics: return "simulate-vehs's Monte Carlo statistics";
    case FileKind::Other: break;
  }
  return "neither a model file nor the statistics of fpk-stationary or simulate-vehs";
}

}  // namespace vehs::tools
