#pragma once
// What a model's held-out innovations show (confirmation.hpp: ResidualSignature): memory,
// heavy tails, a variance that follows the state, correlation with the input, a spectral line.
#include "vehs/core/dataset.hpp"
#include "vehs/diagnose/confirmation.hpp"
#include "vehs/likelihood/filter.hpp"

namespace vehs::diagnose {

/// From the filter's one-step predictions of `held` (every record one block; its first sample
/// is not scored). `dt`: the sampling interval (frequencies in rad per time unit).
ResidualSignature residual_signature(const Dataset& held, const likelihood::FilterTrace& trace, double dt);

}  // namespace vehs::diagnose
