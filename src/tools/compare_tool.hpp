#pragma once
// vehs-compare: a table of true / reported / learned parameters with standard errors, and the
// stationary response from fpk-stationary next to Monte Carlo.
#include "tools/app.hpp"
#include "tools/config.hpp"

namespace vehs::tools {

const ConfigSchema& compare_schema();
int run_compare(Config& config, const AppOptions& app);

}  // namespace vehs::tools
