#pragma once
// simulate-vehs: key table (the single source of --help), parsing of a config into
// SimulationOptions / StatisticsOptions, and running a parsed job (simulate, write the records and
// the statistics). apps/simulate_vehs.cpp calls simulate_main; tests use the parts directly.
#include <string>
#include <vector>

#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/progress.hpp"
#include "vehs/sim/simulate.hpp"

namespace vehs::tools {

struct SimulateJob {
  Model model;
  nlohmann::ordered_json model_sections;  ///< other sections of the model file (echoed in the summary)
  sim::SimulationOptions options;
  std::string output;            ///< measurement file (.csv or .npy); empty: none
  bool record_velocity = true;   ///< write the y column
  bool with_statistics = false;
  sim::StatisticsOptions statistics;
  std::string statistics_json, px_csv, py_csv, pxy_csv;
  std::string summary;           ///< run report JSON; empty: none
  std::string config_file;
  /// harmonic_forcing phase of each trajectory (records started at unrelated times; from the
  /// config's record_phases or the model file's likelihood.record_phases); empty: the model's
  std::vector<double> record_phases;
  /// Electrical constants for the mean power in W (config `harvester`, else the model file's).
  nlohmann::json harvester = nlohmann::json::object();
  /// statistics.parameters: the power's error also carries the fitted parameters' covariance.
  bool power_parameters = false;
};

/// The key table of simulate-vehs.
const ConfigSchema& simulate_schema();

/// Parses and checks a loaded config (model, options, drive file, statistics); throws a
/// one-line vehs::Error naming the file and key. `drive`: the recorded drive in memory, sampled
/// at dt (one series shared by all trajectories, or one per trajectory; vehs.simulate), instead
/// of the config's drive file.
SimulateJob simulate_job_from_config(const Config& config,
                                     const std::vector<std::vector<double>>* drive = nullptr);

/// What a job simulates: the records (unless the job only wants statistics), the statistics
/// (with_statistics) and the run's summary; a drive is applied as the model was fitted
/// (estimator.input) and record_phases run record by record.
struct SimulateRun {
  Dataset data;
  sim::MonteCarloStatistics statistics;
  sim::SimulationSummary summary;
  nlohmann::ordered_json power;  ///< "mean_power" of the statistics (with_statistics only)
};
SimulateRun simulate_job(const SimulateJob& job, const ProgressCallback& progress);

/// Runs a job: simulates, writes the outputs atomically, reports on stderr unless quiet.
/// Returns the exit status (0).
int run_simulate_job(const SimulateJob& job, const AppOptions& app);

/// The body of simulate-vehs: parse, check, run.
int run_simulate(Config& config, const AppOptions& app);

}  // namespace vehs::tools
