#pragma once
// How a recorded input was applied between its samples, read from the samples themselves
// (identify-vehs's `likelihood.input: "auto"`, the default).
//
// The samples cannot tell a held staircase (a DAC at the sampling clock) from a smooth signal
// that was sampled; the spectrum tells the usual cases apart. A drive that is white or broadband
// up to the Nyquist frequency is what a zero-order hold of independent values looks like (the
// simulator's zoh drive of a random sequence puts ≈ 25 % of its power in the top quarter of the
// band); an input with no power near Nyquist is a band-limited signal — a shaker's base
// acceleration measured by an accelerometer behind its anti-alias filter, the Silverbox's
// multisine (band edge at 2/3 of Nyquist) — and is reconstructed by band-limited interpolation.
// On Silverbox zoh gave a free-run RMSE of 18.8 mV against 0.41 band-limited; an outside tester's
// rig in mm (a smooth measured base acceleration, 8 samples a period) got k₁, k₃, β and 2D 3.6–7 SE
// off with zoh and within 2.2 SE with an interpolating input.
#include <string>

#include "vehs/core/dataset.hpp"
#include "vehs/core/fit_info.hpp"

namespace vehs::likelihood {

struct InputReading {
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  double high_band_share = 0.0;  ///< share of the input's power above 3/4 of the Nyquist frequency
  std::string reason;            ///< one line, with the share
};

/// The share below which a sampled input is read as band-limited. A held sequence of independent
/// values has 25 %; a smooth input's zero-order hold errs by about (2π f_rms Δt)²/3 of its
/// variance (34 % for an 80 Hz drive at 500 Hz, whose share is 1.8 %), while band-limited
/// interpolation errs by about its power beyond Nyquist: interpolation wins well before 10 %.
inline constexpr double kBandLimitedShare = 0.10;

/// Band-limited when the input's power above 3/4 of the Nyquist frequency (Welch, records of at
/// least 64 samples, mean removed per record) is below kBandLimitedShare of its total, else zoh.
/// A DAC that holds a smooth waveform at the sampling clock is read as band-limited (its samples
/// are those of a smooth signal); vehs::fit then lets the likelihood decide between the two
/// (vehs/fit/refinement.hpp).
/// Data without an input (or too short to tell) read as zoh with the reason.
InputReading read_input_interpolation(const Dataset& data);

}  // namespace vehs::likelihood
