#pragma once
// The config keys of measured data, shared by identify-vehs and diagnose-vehs: which columns
// (or, for 2-D .npy and .mat matrices, the names of the columns), dt, the sampling tolerances
// and gap policy, detrending, and the units of the data. Reading reports its warnings (time
// jitter, split records) on stderr and as a JSON summary for the output files.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::tools {

/// The keys columns, dt, sampling, detrend and units, with their --help.
std::vector<KeySpec> measurement_keys();

struct LoadedData {
  Dataset data;
  ReadSummary summary;
  std::string detrend;  ///< "none" or "mean"
};

/// The reader options of a config (`need_u`: the model or dictionary uses the drive, the files
/// must have it; `read_present_u`: an input column is read when a file has one, unless it names
/// another role's column).
ReadOptions read_options(const Config& c, bool need_u, bool read_present_u = false);
/// Reads the config's `data` files, prints the reader's warnings on stderr (unless quiet) and
/// detrends.
LoadedData load_measurements(const Config& c, bool need_u, const AppOptions& app, bool read_present_u = false);
/// The same with explicit reader options (vehs.read: the drive read whenever a file has it).
LoadedData load_measurements(const Config& c, const ReadOptions& options, bool quiet);
/// The reading summary for output files: gaps, missing runs, dropped pieces, largest jitter.
nlohmann::ordered_json read_summary_json(const ReadSummary& s);

/// The name of the input column the config reads: columns.u, or "u".
std::string input_column_name(const Config& c);

/// The optional `units` block ({"length": "mm", "time": "s", "input": "V"}), checked; an empty
/// object when absent.
nlohmann::ordered_json units_block(const Config& c);
/// An axis label with the unit of a quantity from a units block, by the tables' rule
/// (vehs/io/parameter_units.hpp): `what` is "x", "v", "t", "u", "f" (frequency), "b2"
/// (acceleration), "a22" (variance rate), "v2", "1/x", "psd_x" or "" (no unit); "x [mm]".
std::string with_unit(const std::string& label, const std::string& what, const nlohmann::json& units);

}  // namespace vehs::tools
