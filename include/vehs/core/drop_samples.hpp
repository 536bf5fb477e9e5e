#pragma once
// Removing samples from records without letting an increment span the gap: each record is cut
// at the removed samples into the pieces between them (the glitch and flat-stretch checks).
#include <cstddef>
#include <vector>

#include "vehs/core/dataset.hpp"

namespace vehs {

struct SampleRef {
  std::size_t record = 0;  ///< index in Dataset::records
  std::size_t sample = 0;  ///< index within the record
};

/// A copy of `data` without the `removed` samples (ascending record, sample): every record cut
/// there into pieces (same source, id and dt; t0 and first_line of each piece); pieces shorter
/// than `min_samples` (at least 2) are left out.
Dataset drop_samples(const Dataset& data, const std::vector<SampleRef>& removed, std::size_t min_samples);

}  // namespace vehs
