#pragma once
// Checks of measurement data that need the config (identify-vehs, diagnose-vehs, through
// load_measurements): isolated glitch samples (vehs/core/glitches.hpp)
// handled by the config key `glitches`: "error" (default: stop, naming the rows), "drop" (cut the
// records at the glitches, reported on stderr) or "keep" (data with genuine single-sample spikes).
#include <string>

#include "tools/config.hpp"
#include "vehs/core/dataset.hpp"

namespace vehs::tools {

/// The `glitches` key of the measurement keys (measurement_config.hpp).
KeySpec glitches_key_spec();

/// Applies the checks to freshly read `data`; returns the data to fit (without dropped glitches,
/// which are reported on stderr).
Dataset checked_measurements(const Config& config, Dataset data);

}  // namespace vehs::tools
