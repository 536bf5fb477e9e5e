#pragma once
// A share of the data on which a fit is started cheaply (the warm start of fit_support, the
// comparison of hidden-state starts).
#include "vehs/core/dataset.hpp"

namespace vehs::likelihood::detail {

/// About `share` of every record: eight evenly spaced pieces of it (so that the pieces cover
/// the record's range of amplitudes), or, with per-record parameters (phases: `keep_records`),
/// the leading share of every record (one record per record). At least 64 samples a record.
Dataset warm_start_share(const Dataset& data, double share, bool keep_records);

}  // namespace vehs::likelihood::detail
