#pragma once
// The start of the measurement noise's sd when none is given.
//
// Why. The likelihood is steep in the measurement sd σ when the data carry little sensor noise:
// on 32 noise-free records of a bistable Duffing with colored_noise (issue 13's case, seed 100;
// Δt 0.05, 128 000 samples) log L is 4.4·10⁵ at σ = 1 % of std(x) and 7.1·10⁵ at the maximum
// (σ → 0). From the former fixed start of 1 % Ceres left the moment start along τ → 0 and stopped
// unconverged at τ 0.018 (truth 0.6), log L 1900 below the maximum, after 47 s; from a nearly
// equal start (0.007 absolute) it converged — far from the maximum the path is fragile. From
// the grid's best start (here 0.01 %, log L 7.12·10⁵) it converges to τ 0.590 ± 0.024 in 13
// iterations and 5 s (tests/likelihood/test_measurement_noise_start.cpp).
#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/observed_model.hpp"

namespace vehs::likelihood::detail {

/// Of σ = 3 %, 1 %, 0.3 %, 0.1 %, 0.03 % and 0.01 % of std(x), the one at which `start` (its
/// other values as given) has the highest log-likelihood, evaluated on about 10⁵ samples of the
/// data (warm_start_share; `keep_records` with per-record parameters). 1 % when no σ can be
/// evaluated. Throws vehs::Error when the records have zero variance.
double measurement_sd_start(const ObservedModel& start, const Dataset& data, const FilterOptions& fo,
                            bool keep_records);

}  // namespace vehs::likelihood::detail
