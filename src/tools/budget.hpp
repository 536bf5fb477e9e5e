#pragma once
// Budgets of a run, estimated from its config before any work is done: integration steps (or a
// solver's unit of work), memory and output size. An estimate above its limit is refused with one
// line giving the estimate, the limit, what lowers it and how to run anyway ("force": true in the
// config, or --force). The limits are documented in docs/config.md ("Budgets").
// (Tools layer: not part of the library's public API.)
#include <string>
#include <vector>

#include "tools/config.hpp"

namespace vehs::tools {

/// Integration steps of simulations (records x samples x substeps, burn-in included) and
/// operations of the regression (rows x terms^2 + terms^4): about 20 min to a few hours on a core.
inline constexpr double kMaxSteps = 1e11;
/// fpk-stationary: grid cells x solves of a (swept) direct solve: ~19 h on a core at 400x400.
inline constexpr double kMaxCellSolves = 1e10;
/// Bytes of the files a run writes.
inline constexpr double kMaxOutputBytes = 2e10;
/// Memory: this fraction of physical memory (vehs::detail::default_memory_limit).
inline constexpr double kMaxMemoryFraction = 0.75;

enum class Resource { Steps, CellSolves, Memory, Output };

struct Estimate {
  Resource resource;
  double amount = 0.0;  ///< steps, cell solves or bytes
  std::string what;     ///< what is counted, e.g. "integration steps (100 records x 1e+06 samples)"
  std::string lower;    ///< what lowers it, e.g. "fewer trajectories, a shorter duration or a larger dt"
};

/// The limit of `resource` (memory: kMaxMemoryFraction of this machine's physical memory).
double budget_limit(Resource resource);

/// The config key that lifts the limits (the same in every tool's schema).
KeySpec force_key();

/// True when the config sets "force": true (or --force was given).
bool forced(const Config& c);

/// Refuses the first estimate above its limit, unless `c` sets "force": true: a vehs::Error
/// "<file>: the run needs about 2e+12 integration steps (...) (limit 1e+11): <lower>, or set
/// \"force\": true (--force) to run it anyway".
void check_budget(const Config& c, const std::vector<Estimate>& estimates);

}  // namespace vehs::tools
