#pragma once
// Internal: the rows the ULI lens can read. Its expansion in h holds where the drift's stiffness
// ω·h = √|∂b/∂x|·h is small; a y² diffusion's rare velocity bursts carry x into a stiff wall
// (ω·h up to ≈ 10 on the pentastable x⁹ potential), where the lens's error is a smooth force of a
// few samples that pulls every moment it enters (issue 13, bench/results/diagnose_calibration_log.md). The rows
// whose stencil reaches there are left out: of the sampling rule's lag statistics
// (standardized_moments) and of the drift and diffusion passes of a state-dependent diffusion.
#include <cstddef>
#include <vector>

#include "drift_pass.hpp"
#include "streaming.hpp"

namespace vehs::identify::detail {

/// The stiffness ω·h beyond which a row is left out: the lens's expansion needs ω·h small (at 0.5
/// its O((ωh)²) error is a few per cent of â).
inline constexpr double kLensStiffnessLimit = 0.5;

/// keep[j − first] for rows [first, first + count) of a record: 1 where the lens's stencil (rows
/// j − k, j, j + k, those of the record's rows that exist) stays where ω·h < kLensStiffnessLimit
/// under the drift `dm`, ω·h of a row taken at its x and at x ± |v|·h, the path's reach over the
/// stencil: a fast row can bounce off the wall between two samples that both lie outside it (with
/// the true drift, seed 202 of bench/identify_wall_rows.py: rows with |v| > 15 read z/a22 ≈ 24
/// with the samples alone, 0.7 with the reach; the diffusion fit's q_y2 0.122 → 0.101).
void lens_keep(const Context& cx, const DriftModel& dm, const Record& rec, std::size_t first, std::size_t count,
               std::vector<char>& keep);

/// Moves the kept rows of a block (keep[c] for its rows c < b.m) to its front, their positions
/// into `rows`; returns their number.
int compact_rows(RowBlock& b, const char* keep, int* rows);

/// Where the stiffness limit would leave out half of the rows or more (coarse sampling, a large
/// stride: the lens's expansion is what the data are read with), no row is left out.
inline bool mask_holds(double kept, double rows) { return kept >= 0.5 * rows; }

}  // namespace vehs::identify::detail
