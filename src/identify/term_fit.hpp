#pragma once
// Internal: identify for the dictionary terms alone (no dynamic effects): pilot and sampling
// diagnosis, estimator and stride, drift pass and selection, diffusion pass and selection, the
// drift refitted with the final diffusion, standard errors. identify() dispatches here; the
// dynamic-effect fits call it with the fitted dynamic force as Options::known_force.
#include "vehs/identify/identify.hpp"

namespace vehs::identify::detail {

Result identify_terms(const Dataset& data, const Options& options);

}  // namespace vehs::identify::detail
