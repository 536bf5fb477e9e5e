#pragma once
// Checks of measurement data that need the config (identify-vehs, diagnose-vehs, through
// load_measurements): isolated glitch samples (vehs/core/glitches.hpp) and flat stretches
// (vehs/core/flat_stretches.hpp), handled by the config keys `glitches` and `flat_stretches`:
// "error" (default: stop, naming the rows), "drop" (cut the records there, reported on stderr)
// or "keep" (data with genuine single-sample spikes or repeats).
#include <string>

#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"

namespace vehs::tools {

/// The `glitches` key of the measurement keys (measurement_config.hpp).
KeySpec glitches_key_spec();

/// The `flat_stretches` key (runs of one repeated value: vehs/core/flat_stretches.hpp).
KeySpec flat_stretches_key_spec();

/// Applies the checks to freshly read `data`; returns the data to fit (without dropped glitches,
/// which are reported on stderr).
Dataset checked_measurements(const Config& config, Dataset data);

}  // namespace vehs::tools
