#pragma once
// diagnose-vehs: key table, options from a config, and the run (diagnosis, JSON, report folder,
// history), so that tests can drive the complete command-line path in-process.
#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/diagnose/diagnose.hpp"

namespace vehs::tools {

/// The key table of diagnose-vehs (docs/config.md plus the diagnosis settings).
const ConfigSchema& diagnose_schema();

/// Options of the diagnosis from a config.
diagnose::Options diagnose_options(const Config& c);

/// The body of diagnose-vehs.
int run_diagnose(Config& c, const AppOptions& app);

}  // namespace vehs::tools
