#pragma once
// The simulate-vehs configuration (contracts.md §3): key table (the single source of --help),
// parsing into SimulationOptions / StatisticsOptions, and running a parsed job. The executable
// apps/simulate_vehs.cpp is a thin wrapper around these; tests use them directly.
#include <string>

#include "vehs/core/app.hpp"
#include "vehs/core/config.hpp"
#include "vehs/core/model.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::sim {

struct SimulateJob {
  Model model;
  SimulationOptions options;
  std::string output;            ///< measurement file (.csv or .npy); empty: none
  bool record_velocity = true;   ///< write the y column
  bool with_statistics = false;
  StatisticsOptions statistics;
  std::string statistics_json, px_csv, py_csv, pxy_csv;
  std::string summary;           ///< run report JSON; empty: none
  std::string config_file;
};

/// The key table of simulate-vehs.
const ConfigSchema& simulate_schema();

/// Parses and checks a loaded config (model, options, drive file, statistics); throws a
/// one-line vehs::Error naming the file and key.
SimulateJob simulate_job_from_config(const Config& config);

/// Runs a job: simulates, writes the outputs atomically, reports on stderr unless quiet.
/// Returns the exit status (0).
int run_simulate_job(const SimulateJob& job, const AppOptions& app);

}  // namespace vehs::sim
