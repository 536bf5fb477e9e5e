#pragma once
// simulate-vehs's `validate` mode: the free-run validation of system identification. The model
// (no process or measurement noise) is driven by a test record's recorded input from the
// measured initial state, with the input applied as in the fit (the model file's
// estimator.input); the RMSE after a transient is reported per segment, and the measured and
// simulated series are written with a figure. Numerics: vehs/likelihood/free_run.hpp.
#include <string>
#include <vector>

#include "tools/app.hpp"
#include "tools/config.hpp"
#include "vehs/core/model.hpp"

namespace vehs::tools {

/// The help text of simulate-vehs's `validate` key.
extern const char* const kValidateHelp;

/// Runs the validation of `model` described by the config's `validate` object; writes its
/// outputs atomically and prints the table. Throws a one-line vehs::Error before writing
/// anything for bad input (sampling mismatch, short input, diverging run, bad segments).
int run_validation(const Model& model, const Config& c, const AppOptions& app);

}  // namespace vehs::tools
