#pragma once
// The data's dominant angular frequency in units of the sampling interval, ω̂·Δt, from the
// increments of x at lags 1 and 2 (insensitive to white sensor noise): for x = A cos(ωt) + ε,
//     D_j = Var(x_{k+j} − x_k) = 4 Var(x) sin²(jωΔt/2) + 2σ²,
// so (D₂ − D₁)/(4 Var x) = q (3 − 4q) with q = sin²(ω̂Δt/2); for broadband x, ω̂ is the
// variance-weighted mean frequency. The moment estimators' expansions in Δt and the sampling
// diagnosis's readings of the ULI residuals assume ω̂Δt small (vehs/likelihood/adequacy.hpp).
#include "vehs/core/dataset.hpp"

namespace vehs {

/// ω̂·Δt of the data (pooled over records, each record's mean removed); NaN when undefined
/// (constant or too short records).
double dominant_omega_dt(const Dataset& data);

}  // namespace vehs
