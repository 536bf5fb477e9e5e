#pragma once
// Isolated glitch samples: one sample of a record far off the line through its neighbours (a
// sensor dropout, a corrupted line of a file). One such sample can dominate every moment-based
// estimate (one x = 0.5 in a clean record made identify-vehs estimate a sensor noise of 2.8e10),
// so the tools look for them before fitting.
//
// Rule: r_i = x_i − (x_{i−1} + x_{i+1})/2 (half the second difference) for interior samples;
// σ = 1.4826·MAD(r) of the record (robust: the glitches themselves do not inflate it; estimated
// from at most 2^17 evenly spaced r_i, so memory does not grow with the record), and at least
// the rounding noise of r, q·√(1.5/12), when the values lie on a grid of step q (quantisation.hpp:
// most r_i of values printed "%.2f" are exactly 0 and MAD is round-off). Sample i is an
// isolated glitch when |r_i| > threshold·σ and both neighbours show the signature of one displaced
// sample, r_{i±1} ≈ −r_i/2 (within |r_i|/4), while r_{i±2} stays below |r_i|/4: a steep but smooth
// feature of the signal (an impact, a fast transient) does not have that shape. Near a record's
// ends the r that do not exist are left out of the signature; the first (last) sample, which has
// no r of its own, is tested one-sided: a displacement g of it makes its one neighbour's
// r_1 = −g/2 (r_{n−2}) while r_2 and r_3 (r_{n−3}, r_{n−4}) stay below |r_1|/4, and it is a glitch
// when |r_1| > threshold·σ (the same false-alarm rate; g must be twice an interior glitch's). A
// truncated last line ("3,49.99,0.") or a 0 logged at a record's start is caught like any
// other glitch; an offset step between the first two samples cannot be told from it. For Gaussian
// r the false-alarm probability per sample at the default threshold 12 is 2·Φ(−12) ≈ 4e-33.
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"

namespace vehs {

struct Glitch {
  std::size_t record = 0;  ///< index in Dataset::records
  std::size_t sample = 0;  ///< index within the record
  std::size_t line = 0;    ///< line in the file (record.first_line + sample)
  double x = 0.0;          ///< the glitch value
  double score = 0.0;      ///< |r_i| / σ
};

/// The isolated glitches of every record (ascending record, sample).
std::vector<Glitch> find_glitches(const Dataset& data, double threshold = 12.0);

/// "data.csv: line 2345 (x = 0.5, 3.1e+03 sigma)[, ...]": up to `max_listed` glitches named.
std::string describe_glitches(const Dataset& data, const std::vector<Glitch>& glitches, std::size_t max_listed = 5);

/// A copy of `data` without the glitch samples: each record is cut at its glitches into the pieces
/// between them (same source, id and dt; t0 and first_line of each piece), so that no increment
/// spans a removed sample; pieces shorter than `min_samples` are left out.
Dataset drop_glitches(const Dataset& data, const std::vector<Glitch>& glitches, std::size_t min_samples = 16);

}  // namespace vehs
