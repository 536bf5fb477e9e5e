#pragma once
// Files and figures of fpk-stationary (tools layer): the density (CSV or .npy), marginals, the statistics
// JSON of docs/outputs.md#statistics, sweep tables, and gnuplot figures in the style of the paper's
// Fig. 3b/4 (density heat map, marginals with the potential) and Fig. 5 (sweep curves/surfaces).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/fpk/stationary.hpp"

namespace vehs::tools {

/// Writes the density atomically: `.npy` → float64 array of shape (nx, ny), p[i][j] at
/// (x_i, y_j) (grid in the JSON); anything else → CSV with columns x,y,p (x outer, y inner).
void write_density(const std::string& path, const fpk::StationaryResult& result);
/// Writes p(x) (columns x,p,U) and p(y) (columns y,p) as CSV.
void write_marginals(const std::string& x_path, const std::string& y_path, const fpk::FpkModel& model,
                     const fpk::StationaryResult& result);

/// The statistics object: "E[X^2]", "E[Y^2]", "E[XY]", "E[X]", "E[Y]", "boundary_mass",
/// "grid", "wells", "identities", "solve".
nlohmann::ordered_json result_to_json(const fpk::StationaryResult& result);

/// The sweep table: one row per point (parameters, E[X^2], E[Y^2], E[XY], boundary_mass,
/// residual, wells masses as well_1..well_k for the largest well count, ok).
void write_sweep_table(const std::string& path, const fpk::SweepResult& sweep);
nlohmann::ordered_json sweep_to_json(const fpk::SweepResult& sweep);

/// Figures (SVG) into `dir`; each with its data CSV and .gp script beside it. Returns the paths
/// of the rendered figures (empty entries are skipped when gnuplot is missing).
/// `units`: the model file's units block (axis labels). The heat map shows the region where the
/// density exceeds 1e-4 of its peak (the automatic domain reaches far into the tails).
std::vector<std::string> density_figures(const std::string& dir, const fpk::FpkModel& model,
                                         const fpk::StationaryResult& result,
                                         const nlohmann::json& units = nlohmann::json::object());
std::vector<std::string> sweep_figures(const std::string& dir, const fpk::SweepResult& sweep);

}  // namespace vehs::tools
