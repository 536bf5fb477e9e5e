#pragma once
// Where a model's diffusion a22 is lowest over the states its data visit. A variance rate must be
// ≥ 0; a fitted polynomial diffusion (2D + 2Q x² + c x⁴ …) can turn negative inside the range of
// the data it was fitted to when the data do not support its terms (quantised or clipped records
// read at the wrong stride: a22 < 0 beyond |x| = 77 counts of records reaching 87). identify-vehs
// refuses to write such a model; simulate-vehs and diagnose-vehs refuse to read it.
#include <cstddef>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs {

/// The lowest a22 over the data's samples, where and how often it is negative.
struct DiffusionInData {
  double a22 = 0.0;             ///< the lowest value
  double x = 0.0, y = 0.0;      ///< the state where it is reached
  std::size_t record = 0;       ///< index of the record
  std::size_t sample = 0;       ///< index of the sample in its record
  std::size_t negative = 0;     ///< samples where a22 < 0
  std::size_t samples = 0;      ///< samples looked at
};

/// a22 of `model` at every sample (x_i, y_i), y from the records' velocity column when read,
/// else the central difference (x_{i+k} − x_{i−k}) / (2kΔt) at `stride` k (the first and last k
/// samples of each record are skipped). Records shorter than 2k + 1 samples are skipped.
DiffusionInData lowest_diffusion_in_data(const Model& model, const Dataset& data, int stride);

}  // namespace vehs
