#pragma once
// The diagnose-vehs executable as library functions, so that tests can drive the complete
// command-line path (config → data + model → JSON, report folder, history) in-process.
#include "vehs/core/app.hpp"
#include "vehs/core/config.hpp"
#include "vehs/diagnose/diagnose.hpp"

namespace vehs::diagnose {

/// The key table of diagnose-vehs (contracts.md §3 plus the diagnosis settings).
const ConfigSchema& app_schema();

/// Options of the diagnosis from a config.
Options options_from_config(const Config& c);

/// The body of diagnose-vehs.
int run_app_body(Config& c, const AppOptions& app);

/// main() of diagnose-vehs.
int main(int argc, char** argv);

}  // namespace vehs::diagnose
