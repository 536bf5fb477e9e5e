#pragma once
// identify-vehs: key table, options from a config, and the run (identification, or a consistency
// study when `study` is given), so that tests can drive the complete command-line path
// (config → data → model file) in-process.
#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/identify/study.hpp"
#include "vehs/io/measurements.hpp"

namespace vehs::tools {

/// The key table of identify-vehs (docs/config.md plus the estimator settings).
const ConfigSchema& identify_schema();

/// Options of the estimator from a config (libraries, effects, estimator, sparsity...).
identify::Options identify_options(const Config& c);

/// Study options from the config's `study` object.
identify::StudyOptions study_options(const Config& c);

/// The body of identify-vehs: identification (or a consistency study when `study` is given).
int run_identify(Config& c, const AppOptions& app);

}  // namespace vehs::tools
