#pragma once
// When the moment estimators (identify's forward / ULI / noisy: expansions in the sampling
// interval Δt) cannot be vouched for, and the exact-sampling likelihood should refine them.
//
// The rule (identify-vehs's estimator "auto" applies it after the moment fit):
//  * the data's dominant angular frequency ω̂ is measured from the increments of x at lags 1
//    and 2, which is insensitive to white sensor noise: for x = A cos(ωt) + ε,
//        D_j = Var(x_{k+j} − x_k) = 4 Var(x) sin²(jωΔt/2) + 2σ²,
//    so (D₂ − D₁)/(4 Var x) = q (3 − 4q) with q = sin²(ω̂Δt/2); for broadband x, ω̂ is the
//    variance-weighted mean frequency;
//  * the leading discretisation bias of the second-difference kinematics is relative
//    (ω̂Δt)²/12 on the restoring force (the h²/12·x'''' term; its damping and Itô-correction
//    counterparts are of the same order — measured: β −18 % at ω·Δt = 1, bench/results);
//  * the expansions are not vouched for when ω̂Δt ≥ 0.2 (fewer than ~31 samples per period) and
//    that bias exceeds the best relative standard error of the moment fit's drift coefficients
//    (a bias of more than one SE makes the intervals wrong), or when the model has a recorded
//    input and ω̂Δt ≥ 0.1: the moment fit regresses on u_k held over the interval, a delay of
//    Δt/2, i.e. a phase error of ω̂Δt/2 ≥ 5 % of a radian in the forcing.
// Silverbox (ω̂Δt ≈ 0.7, recorded input) and the bistable Duffing at ω·Δt 0.5 and 1.0 are not
// vouched for; the paper's data (Δt = 0.001) are.
#include <string>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs::likelihood {

struct SamplingAdequacy {
  double omega_dt = 0.0;          ///< ω̂·Δt (NaN when the data are too short or a constant)
  double bias = 0.0;              ///< (ω̂Δt)²/12: relative bias of the expansions
  double best_relative_se = 0.0;  ///< min over drift terms of stderr / |coef| (inf: none stated)
  bool recorded_input = false;    ///< the model has a `u` term
  bool vouched = true;            ///< the moment fit can stand on its own
  std::string reason;             ///< one line, for the report
};

/// ω̂·Δt of the data (pooled over records, each record's mean removed); NaN when undefined.
double dominant_omega_dt(const Dataset& data);

/// The rule above for a moment fit `fit` of `data`.
SamplingAdequacy assess_sampling(const Model& fit, const Dataset& data);

}  // namespace vehs::likelihood
