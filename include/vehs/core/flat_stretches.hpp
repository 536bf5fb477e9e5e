#pragma once
// Flat stretches: runs of exactly repeated values of x in a record, longer than the record's own
// repeats explain. Loggers write a dropout as 0 or as the last good value, a stuck sensor repeats
// its reading, a saturated one its limit; a continuous signal sampled with a fine ADC almost
// never repeats a value. One such stretch can dominate the moment estimates (50 zeros in one of
// 50 records of a Duffing in mm: β 51 against 5 and no diffusion term; 20 stuck samples in a
// record of 30 000: 2D −32 %, 10 SE), so the tools look for them before fitting.
//
// Rule, per record of N samples: a record whose consecutive pairs repeat inside short runs
// (fewer than 5 equal values) at least once in 1000 is quantised and is not checked — an ADC's
// or a printout's values repeat there legitimately, and in long runs at the turning points (a
// new user's 10-, 12- and 16-bit records at 1–20 kHz and values printed with 2–3 decimals had
// such runs of 10–400 samples and short-run repeat shares of 0.002–0.33; the first form of this
// rule, without this test, stopped them with false alarms). In the other records (float data,
// Silverbox: short-run share 3e-5, longest run 2): p = the share of consecutive pairs that are
// equal (at least 1/N); if repeats were independent with that probability, a run of L equal
// values would occur with probability about N·p^(L−1); a run is flagged when that is below 1e-9
// and L ≥ 5. A record with most of its consecutive pairs equal is quantised too (a noise-free ADC
// far faster than the signal: every repeat in a long run). In a quantised record a dropout or a
// held reading shows by the jump into or out of its run (vehs/core/detail/stepped_runs.hpp); a
// reading held at coarse sampling while the signal swings back to near it is not caught. Clipping
// is caught in every record by the pile-up of samples at its extreme value
// (vehs/core/detail/clipped_runs.hpp): every run there is flagged, however short.
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"

namespace vehs {

struct FlatStretch {
  std::size_t record = 0;  ///< index in Dataset::records
  std::size_t sample = 0;  ///< index of its first sample within the record
  std::size_t length = 0;  ///< samples
  std::size_t line = 0;    ///< line of its first sample in the file (record.first_line + sample)
  double x = 0.0;          ///< the repeated value
  bool clipped = false;    ///< a run at a quantised record's piled-up extreme (detail/clipped_runs.hpp)
};

/// The flat stretches of every record (ascending record, sample).
std::vector<FlatStretch> find_flat_stretches(const Dataset& data);

/// "data.csv: lines 2001-2050 (50 samples of x = 0)[, ...]": up to `max_listed` named.
std::string describe_flat_stretches(const Dataset& data, const std::vector<FlatStretch>& stretches,
                                    std::size_t max_listed = 5);

/// A copy of `data` without the stretches' samples: each record cut there into the pieces
/// between them (as drop_glitches), pieces shorter than `min_samples` left out.
Dataset drop_flat_stretches(const Dataset& data, const std::vector<FlatStretch>& stretches,
                            std::size_t min_samples = 16);

}  // namespace vehs
