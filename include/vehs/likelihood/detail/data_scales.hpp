#pragma once
// The data's own scales, for start values and priors: the variance of x and the mean square of
// its difference quotient (≈ E[y²] for a sensor sampling a continuous process).
#include "vehs/core/dataset.hpp"

namespace vehs::likelihood::detail {

/// Sample variance of every x of the data pooled (0 for fewer than 2 samples).
double x_variance(const Dataset& data);

/// Mean over the records' consecutive pairs of ((x_{k+1} − x_k)/Δt)² (0 without pairs).
double mean_squared_rate(const Dataset& data);

}  // namespace vehs::likelihood::detail
