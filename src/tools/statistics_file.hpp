#pragma once
// The Monte Carlo statistics file of simulate-vehs: {"E[X^2]": ..., "stderr": {...}, "records": ...,
// "histograms": {...}} and the histograms p(x), p(y) as CSV (x,p) and p(x, y) as CSV (x,y,p) on
// cell centres.
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/sim/simulate.hpp"

namespace vehs::tools {

nlohmann::ordered_json statistics_to_json(const sim::MonteCarloStatistics& statistics);

/// Writes the JSON (with the keys of `extra` appended) and, with histograms, the CSVs; empty paths
/// are skipped. The JSON names the CSV files. Atomic writes.
void write_statistics(const sim::MonteCarloStatistics& statistics, const std::string& json_path,
                      const std::string& px_csv, const std::string& py_csv, const std::string& pxy_csv,
                      const nlohmann::ordered_json& extra = nlohmann::ordered_json::object());

}  // namespace vehs::tools
