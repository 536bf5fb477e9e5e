#pragma once
// A recorded input (the data's u column) and identify's libraries. The default drift library takes
// the input in as the drive term u: dropped, a driven rig's input is read as noise and the
// library's other terms mimic it (Silverbox: a model without u, free-run RMSE 10x worse, with no
// word). A library given without u leaves the input out, with a warning. What was done goes to
// stderr (unless quiet) and into the model file's data.input.
//
// Driven data have their own default libraries (each applies when the config leaves that library
// out): drift {K1: 4, K2: 3} + u (the Duffing form: cubic stiffness, damping up to x^2*y) and
// diffusion [1]. A free run of the input's response reaches amplitudes beyond the estimation
// data, where the higher powers fitted inside them take over: the likelihood adds x^4 ... x^7 by
// score tests (Silverbox arrow 0.473 mV against 0.405 from the cubic), and with x^5 its fit had a
// positive x^5, a potential that does not confine (no stationary simulation, no bias correction).
// With the input's force in the drift, a state-dependent a22 fitted to the residuals absorbs the
// drift's misfit at large amplitude instead of noise (Silverbox with the default {M: 4}: a22 with
// x^4 and free-run RMSE 1.6 mV instead of 0.32).
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/terms.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs {

struct RecordedInput {
  std::string column;             ///< the data's input column; empty when the data have none
  bool in_drift_library = false;  ///< the drift library holds u
  bool added = false;             ///< u added to the default library because the data have an input
  std::string why;                ///< one line: what was done with the input and why
  std::string warning;            ///< set when a given drift_library leaves the data's input out
};

/// The drift library identify uses for driven data by default: {K1: 4, K2: 3} and u.
std::vector<Term> driven_drift_library();

/// Which of identify's libraries the user gave (the others are defaults that the data's input may
/// replace).
struct LibrariesGiven {
  bool drift = false, diffusion = false;
};

/// What identify does with the data's input (named `column` in messages): when no drift library
/// was given and `data` have an input column, the driven default libraries above replace the
/// defaults in `options` (the diffusion's only when no diffusion library was given either; the
/// kept terms are added); a given library without u while the data have one gets a warning.
RecordedInput use_recorded_input(const Dataset& data, const std::string& column, LibrariesGiven given,
                                 identify::Options& options);

}  // namespace vehs
