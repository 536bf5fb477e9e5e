#pragma once
// The filter's own bias removed by simulation (RefineOptions::bias_correction_datasets).
//
// The Gaussian filter's log-likelihood is not the exact one where the state's law is visibly
// non-Gaussian (filter.hpp), and its score at the true parameters then has a non-zero mean b(θ)
// — a bias of the estimating equation that does not shrink with the record length (the paper's
// model with 2 % sensor noise: diffusion[x^2] +5 %, bench/results/likelihood_score_*.txt). The
// corrected estimate solves score(θ) − b(θ) = 0 to first order:
//     θ̃ = θ̂ − I⁻¹ b̂,   b̂ = mean over B data sets simulated at θ̂ like the data of the filter's
//                           score at θ̂,   I⁻¹ = the fit's covariance (internal scale).
// The data sets copy the data's design: records, lengths, sampling interval, each record's first
// sample (x, and y from its first difference), the recorded input per record (applied as the
// filter applies it), the fitted measurement noise. The simulator (Itô–Taylor 1.5) runs 8 steps
// per filter substep (at least 20); an interpolated input (linear, cubic, band-limited) is held
// at the midpoint of each step, an O((ω_u·h)²) error the filter does not make, so there it runs
// 32 per filter substep (at least 64; records simulated one at a time, at most 2^24 steps each).
// Silverbox, 3 filter substeps: 24 steps per interval moved ω² by 18 SE and 2D by −10 %; 96
// steps by 3.9 and 0.1 SE, the filter's RK4 (a 12-substep filter agrees). b̂ has the covariance I/B, so the corrected estimate's covariance
// is the fit's times (1 + 1/B). The log-likelihood and BIC stay those of the maximum.
// Cost: B simulations and B gradient passes over data of the data's size (a refine takes tens).
// Not available with one harmonic_forcing phase per record (the simulator shares one phase).
#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/detail/parameterization.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs::likelihood::detail {

/// `res` (a fit of `data` with the free parameters of `choice`) corrected in place: values,
/// model, standard errors, covariance, summary.bias_correction. Throws vehs::Error with one line
/// when the model cannot be simulated or the filter fails on a simulated data set.
void correct_filter_bias(Result& res, const Dataset& data, const RefineOptions& o, const FitChoice& choice);

/// Data like `data` (records, lengths, dt, first samples, input) simulated from `model` with
/// `substeps` simulator steps per interval (fewer when a record would need more than 2^24 with an
/// interpolated input); the input applied as `input` (interpolated: held at the midpoints of the
/// steps).
Dataset simulate_like(const ObservedModel& model, const Dataset& data, int substeps, std::uint64_t seed,
                      InputInterpolation input = InputInterpolation::ZeroOrderHold);

}  // namespace vehs::likelihood::detail
