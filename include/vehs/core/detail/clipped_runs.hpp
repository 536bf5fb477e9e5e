#pragma once
// Internal (flat_stretches.cpp): clipping in a quantised record. Its values repeat legitimately,
// so run lengths cannot show a saturated sensor (a second outside tester's 10-bit Duffing at
// 20 kHz clipped at ±81 counts: 15 runs of up to 192 samples, shorter than the record's natural
// runs of up to 214; exit 0 with x and y dropped and x⁵ … x⁹ added). What shows it is a pile-up
// at the extreme value: a smooth density puts about as many samples on the extreme level as on
// the level next to it (a parabolic turning point inside the top level gives the next level
// 0.83× the top's time), and one excursion visits the top level in one run or, when it straddles
// the level boundary, alternates with the next level. A clip puts many samples on the extreme,
// from many excursions, and few on the next level.
#include <cstddef>
#include <vector>

#include "vehs/core/flat_stretches.hpp"

namespace vehs::detail {

/// Appends to `out` every run at the record's largest (and smallest) value when that value holds
/// more than 3× the samples of the next value inwards plus 30, in at least 3 separate runs or in
/// a run more than 3× as long as the longest run at any other value (one clipped excursion);
/// the lowest level's runs first (find_flat_stretches sorts them).
void append_clipped_runs(const double* x, std::size_t n, std::size_t record, std::size_t first_line,
                         std::vector<FlatStretch>& out);

}  // namespace vehs::detail
