#pragma once
// Internals of refine(): one fit of a fixed support, standard errors into the model, and the
// backward elimination by a likelihood criterion.
#include "vehs/likelihood/detail/parameterization.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs::likelihood::detail {

/// Maximum likelihood of the support of `start`; the requested covariance when
/// `final_covariance`, else the inverse Fisher information (cheap, for ranking terms).
Result fit_support(const ObservedModel& start, const Dataset& data, const RefineOptions& o,
                   const FitChoice& choice, bool final_covariance);

/// The uncertainty of `res` from one source, res.covariance: res.stderrs = sqrt(diag), and
/// res.model.model gets them (drift_stderr, diffusion_stderr, effects' stderr_) with its
/// covariance: the block of res.covariance over those parameters (not measurement_sd or the
/// record phases), the same doubles.
void attach_stderrs(Result& res);

/// Backward elimination from the support of `start` (refine.hpp).
Result select_support(const ObservedModel& start, const Dataset& data, const RefineOptions& o,
                      FitChoice choice);

/// Forward steps from `current` (a fit of its support): the candidate term with the largest
/// score-test z² (score_test.hpp) is added and the model refitted while z² and 2ΔlogL pass the
/// criterion; each step is appended to `steps`.
Result add_terms(Result current, const Dataset& data, const RefineOptions& o, const FitChoice& choice,
                 std::vector<SelectionStep>& steps);
/// Upper quantile of χ²₁: q with P(χ²₁ > q) = p.
double chi2_1_upper_quantile(double p);

}  // namespace vehs::likelihood::detail
