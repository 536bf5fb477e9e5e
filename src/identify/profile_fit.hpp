#pragma once
// Internal: identify with dynamic forces (impact_stop, harmonic_forcing,
// electromechanical_coupling) by profile least squares over their nonlinear parameters, alternated
// with the term fit on the target corrected by the fitted force (vehs/identify/dynamic.hpp
// describes the method).
#include "vehs/identify/identify.hpp"

namespace vehs::identify::detail {

Result identify_profile(const Dataset& data, const Options& options);

}  // namespace vehs::identify::detail
