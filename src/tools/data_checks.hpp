#pragma once
// The config keys `glitches` and `flat_stretches` of the data checks (vehs/fit/data_checks.hpp),
// applied by identify-vehs and diagnose-vehs through load_measurements and by the Python package:
// "error" (default: stop, naming the rows), "drop" (cut the records there, reported on stderr)
// or "keep" (data with genuine single-sample spikes or repeats).
#include <string>

#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/fit/data_checks.hpp"

namespace vehs::tools {

/// The `glitches` key of the measurement keys (measurement_config.hpp).
KeySpec glitches_key_spec();

/// The `flat_stretches` key (runs of one repeated value: vehs/core/flat_stretches.hpp).
KeySpec flat_stretches_key_spec();

/// The rules of the config's `glitches` and `flat_stretches` keys.
DataChecks data_checks(const Config& config);

/// Applies the checks to freshly read `data`; returns the data to fit (without dropped glitches,
/// which are reported on stderr).
Dataset checked_measurements(const Config& config, Dataset data);

}  // namespace vehs::tools
