#pragma once
// The identify-vehs executable as library functions, so that tests can drive the complete
// command-line path (config → data → model file) in-process.
#include "vehs/core/app.hpp"
#include "vehs/core/config.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/identify/study.hpp"

namespace vehs::identify {

/// The key table of identify-vehs (contracts.md §3 plus the estimator settings).
const ConfigSchema& app_schema();

/// Options of the estimator from a config (libraries, effects, estimator, sparsity...).
Options options_from_config(const Config& c);

/// Reading options (columns, dt) from a config.
ReadOptions read_options_from_config(const Config& c, bool need_u);

/// Study options from the config's `study` object.
StudyOptions study_from_config(const Config& c);

/// The body of identify-vehs: identification (or a consistency study when `study` is given).
int run_app_body(Config& c, const AppOptions& app);

/// main() of identify-vehs.
int main(int argc, char** argv);

}  // namespace vehs::identify
