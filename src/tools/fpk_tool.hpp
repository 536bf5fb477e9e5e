#pragma once
// fpk-stationary: key table and the run (model → stationary density, marginals, moments,
// wells, identities, figures, parameter sweeps).
#include "tools/app.hpp"
#include "tools/config.hpp"

namespace vehs::tools {

const ConfigSchema& fpk_schema();
int run_fpk(Config& config, const AppOptions& app);

}  // namespace vehs::tools
