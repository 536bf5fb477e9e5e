#pragma once
// Internal: identify with colored_noise (an Ornstein–Uhlenbeck excitation): tau and intensity from
// the residual autocovariance, the drift by GLS on Kalman prediction errors, the white diffusion
// from the residual variance (vehs/identify/dynamic.hpp describes the method).
#include "vehs/identify/identify.hpp"

namespace vehs::identify::detail {

Result identify_colored(const Dataset& data, const Options& options);

}  // namespace vehs::identify::detail
