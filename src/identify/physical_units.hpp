#pragma once
// Internal: identify runs on data scaled to O(1) (vehs/core/scaling.hpp) — the options'
// physical quantities go in scaled, the result comes out in the data's units, and a standard
// error that is not finite is an error naming the parameter and the cause.
#include <vector>

#include "vehs/core/scaling.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::identify::detail {

/// The options in internal units; `force` holds the scaled known force when there is one.
Options options_in_internal_units(const Options& options, const Scales& s, std::vector<double>& force);

/// The result of a fit to internally scaled data, in the data's units: the model (coefficients,
/// errors, covariance, effects, fit) and the report's figures that carry units.
Result result_in_physical_units(Result internal, const Scales& s);

/// Throws vehs::Error naming the first parameter whose standard error is not finite.
void require_finite_standard_errors(const Model& model);

}  // namespace vehs::identify::detail
