#pragma once
// Internal (flat_stretches.cpp): a dropout or a held value in a quantised record. There values
// repeat legitimately, in runs of hundreds of samples at the turning points, so a run's length
// cannot show a dropout (an outside check: 50 samples logged as 0 in the middle of a 12-bit
// bistable record at 20 kHz gave β 11 039 for 6.28 and no stiffness; the same 50 samples held at
// the last reading gave β +41 %, both with exit 0). What shows it is how the signal enters and
// leaves the run: a natural run is where the signal is slow, so it is entered and left by steps
// no larger than the increments around it; a dropout is entered and left by a jump to and from
// the logged value, and a held reading is left by the distance the signal travelled meanwhile
// (its velocity times the run's duration: L times its increments).
#include <cstddef>
#include <vector>

#include "vehs/core/flat_stretches.hpp"

namespace vehs::detail {

/// Appends to `out` every run of at least `min_run` equal values entered or left by a step larger
/// than 4× the largest increment within max(L, 16) samples on either side of the run (the
/// steps into and out of it excluded) and than 3 grid steps (the smallest non-zero increment of
/// the record). A step between two runs of at least `min_run` belongs to the longer (the natural
/// run beside a dropout is not flagged by the dropout's step). Runs at a value in `skip` (clipped
/// levels, already flagged) are left out.
void append_stepped_runs(const double* x, std::size_t n, std::size_t record, std::size_t first_line,
                         std::size_t min_run, const std::vector<double>& skip, std::vector<FlatStretch>& out);

}  // namespace vehs::detail
