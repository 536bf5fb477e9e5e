#pragma once
// Quantised records: values on a grid of step q (integer ADC counts, a scaled count, values
// printed with a fixed number of decimals). Rounding to the grid adds an error e of variance
// q²/12 to every sample; it is white noise only between samples whose increment spreads over
// more than a step: the errors of two samples an increment d ~ N(0, σ²) apart correlate as
// (6/π²) Σ_n exp(−2π²n²σ²/q²)/n², 0.10 at σ = 0.3q, 4e-3 at 0.5q, 2e-9 at σ = q. At a fast rate
// (90 % of consecutive samples equal) the error is a staircase, correlated over many samples.
// identify reads such records at a stride where the increments' spread is at least q and
// corrects its moments for the known white noise q²/12 there (vehs/identify/identify.hpp).
#include <cstddef>

#include "vehs/core/dataset.hpp"

namespace vehs {

/// The grid of a quantised dataset.
struct Quantisation {
  double step = 0.0;          ///< q; 0 when the values are not on a common grid
  int dither_stride = 1;      ///< the smallest stride k (1, 2, 4, …) with sd(x_{i+k} − x_i) ≥ q
  double noise_variance() const { return step * step / 12.0; }
  bool quantised() const { return step > 0.0; }
};

/// The step q of a grid every record's x lies on (each record with its own origin, so that a
/// per-record offset removed by `detrend` keeps the grid), and the stride from which the
/// rounding error is white. Not quantised: fewer than 1 in 8 of the values repeat (the grid
/// is then finer than the data's spacing and its noise negligible), fewer than 1 in 4 of the
/// neighbouring distinct values one step apart, or a value off the grid by more than 1e-3 q.
Quantisation find_quantisation(const Dataset& data);

}  // namespace vehs
