#pragma once
// fpk-stationary: key table and the run (model → stationary density, marginals, moments,
// wells, identities, figures, parameter sweeps).
#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/fpk/stationary.hpp"

namespace vehs::tools {

const ConfigSchema& fpk_schema();

/// The solver settings of a config: scheme and solver options, domain options, the grid
/// request and the sweep axes (empty without `sweep`; names not yet checked against a model).
struct FpkSettings {
  fpk::SolveOptions solve;
  fpk::DomainOptions domain;
  fpk::GridRequest grid;
  std::vector<fpk::SweepAxis> axes;
};
FpkSettings fpk_settings(const Config& config);

int run_fpk(Config& config, const AppOptions& app);

}  // namespace vehs::tools
