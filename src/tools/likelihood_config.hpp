#pragma once
// identify-vehs's `likelihood` config block and `estimator` key, read into the fit's likelihood
// settings (vehs/fit/refinement.hpp).
#include <string>

#include "tools/config.hpp"
#include "vehs/fit/refinement.hpp"

namespace vehs::tools {

/// The help text of the `likelihood` key.
extern const char* const kLikelihoodHelp;

/// Settings from the config's `estimator` (\"likelihood\": always) and `likelihood` block
/// (present: always unless its `use` says otherwise; absent: auto with estimator auto, never
/// with an explicitly named moment estimator).
LikelihoodSettings likelihood_settings(const Config& c);

/// The estimator string for identify's moment fit ("likelihood" → "auto").
std::string moment_estimator_name(const Config& c);

}  // namespace vehs::tools
