#pragma once
// Test signals and data segments for identification and validation: a random-phase multisine
// (the excitation of the Silverbox estimation data, and a broadband recorded input for
// simulated rigs), and a sample range of one record as a data set of its own (estimation and
// test splits).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "vehs/io/measurements.hpp"

namespace vehs::likelihood {

/// Σ_{j=1..lines} amplitude·cos(j·dw·t_i + φ_j), t_i = i·dt, phases uniform (seeded).
std::vector<double> random_phase_multisine(std::size_t samples, double dt, int lines, double dw,
                                           double amplitude, std::uint64_t seed);

/// Samples [first, last) of record `record` as a one-record data set (its t0, first line and
/// source follow the original; x and, when present, u are copied). Throws vehs::Error for a
/// range outside the record.
Dataset slice_record(const Dataset& data, std::size_t record, std::size_t first, std::size_t last);

}  // namespace vehs::likelihood
