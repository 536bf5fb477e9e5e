#pragma once
// One source for a model's uncertainty: the covariance of its estimates (Model::covariance);
// the standard errors (Model::drift_stderr, diffusion_stderr, Effect::stderr_) are the square
// roots of its diagonal.
#include "vehs/core/model.hpp"

namespace vehs {

/// Makes the model's standard errors and covariance agree, the covariance being the source:
/// every parameter the covariance lists ("drift[<term>]", "diffusion[<term>]",
/// "<effect>.<param>") gets stderr = sqrt(covariance(i, i)) (the same doubles); a parameter
/// that has a standard error but no row joins the covariance as an uncorrelated row of
/// variance stderr² (a fit that estimated it apart from the others). A model without a
/// covariance keeps its standard errors. Throws vehs::Error (one line, after `where`) when the
/// covariance is not valid or names a parameter the model does not have.
void standard_errors_from_covariance(Model& m, const std::string& where);

}  // namespace vehs
