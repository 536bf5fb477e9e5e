#pragma once
// Test signals and data segments for identification and validation: a random-phase multisine
// (the excitation of the Silverbox estimation data, and a broadband recorded input for
// simulated rigs), and a sample range of one record as a data set of its own (estimation and
// test splits).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/fit_info.hpp"

namespace vehs::likelihood {

/// Σ_{j=1..lines} amplitude·cos(j·dw·t_i + φ_j), t_i = i·dt, phases uniform (seeded).
std::vector<double> random_phase_multisine(std::size_t samples, double dt, int lines, double dw,
                                           double amplitude, std::uint64_t seed);

/// Samples [first, last) of record `record` as a one-record data set (its t0, first line and
/// source follow the original; x and, when present, u are copied). Throws vehs::Error for a
/// range outside the record.
Dataset slice_record(const Dataset& data, std::size_t record, std::size_t first, std::size_t last);

/// The recorded input u[0 … n) applied as `how` (detail/input_path.hpp), sampled at the
/// midpoints of `factor` equal sub-intervals of every interval: value j of interval k is
/// u(t_k + (j + ½)·Δt/factor), (n − 1)·factor values. Held over each sub-interval, it is the
/// interpolated input to O(Δt/factor) — how simulate-vehs applies an input that was fitted as
/// linear, cubic or band-limited with a simulator that holds its drive per step.
std::vector<double> refine_input(const std::vector<double>& u, int factor, InputInterpolation how);

}  // namespace vehs::likelihood
