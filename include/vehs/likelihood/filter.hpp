#pragma once
// The exact-discretisation likelihood of measured records under an observed model
// (observed_model.hpp), by a continuous–discrete Gaussian filter over the model's state
// (x, y, and the hidden v, η of electromechanical_coupling and colored_noise).
//
// Why this filter. CTSM-R's continuous–discrete extended Kalman filter propagates the mean by
// the drift at the mean and the covariance by the Jacobian at the mean. Here the time update
// integrates the moment equations of the assumed-density Gaussian filter instead
// (detail/moment_system.hpp): the mean follows E[f], the covariance E[∂f]·P + P·E[∂f]ᵀ + E[a22],
// with every expectation exact under the Gaussian — polynomial terms of any degree, and the
// non-smooth ones (sign(y), y·|y|, the hinges of end stops) in closed form. This is what an
// unscented filter approximates with 2n+1 sigma points, without its error for degree > 3
// (x⁹ of the paper's model) and without its coarse treatment of a kink (a sigma point on each
// side of sign(y)); an EKF would linearise sign(y) to slope 0 almost everywhere and lose the
// curvature term 3·m·P_xx of x³. The cost is that of an EKF.
// The time update runs RK4 substeps of these equations over each sampling interval, so it is
// right at any ω·Δt (no expansion in Δt); the recorded drive is held (zero-order hold, like a
// DAC) or interpolated between samples (linear, cubic, band-limited). In a model with Coulomb
// friction, an interval on which no RK4 count keeps the covariance valid (its expected slope
// μ·2φ(0)/√P_yy when the velocity is nearly known: nearly deterministic, quantised closed-loop
// motion) is integrated by backward Euler steps, which stay valid at any stiffness
// (detail/implicit_step.hpp); models without friction keep the plain RK4 retries. The cost
// is bounded: a block may take backward Euler on 8 + n/32 of its n intervals and spend 10 times
// its planned RK4 substeps on retries; a model that needs more is refused as diverged.
//
// Where the Gaussian approximation is good and where it is not (measured against a particle
// filter of the same model: `bench/likelihood.sh gaussian`, bench/results/likelihood_gaussian.txt;
// bistable U = −x²/2 + x⁴/4, β = 0.1, sensor noise 0.05, 500 scored samples):
//  * ω·Δt = 0.5 and 1.0 (Δt = 0.35, 0.7; 2D = 0.04): log L within 0.04 and 1.0 nats of the
//    particle filter's (±0.24, ±0.32), and the quantity estimation uses — the change of log L
//    between β = 0.1 and 0.13 — equal within its error (−0.78 vs −0.79 ± 0.08 at ω·Δt = 1);
//    likewise at four times the noise (2D = 0.16, frequent well changes) at ω·Δt = 0.5;
//  * ω·Δt = 2 (Δt = 1.4): the predictive law of one interval is visibly non-Gaussian (the
//    state can cross the barrier within an interval): log L 10.6 nats (0.02 per sample) below
//    the particle filter's, although the β contrast still agrees (2.28 vs 1.93 ± 0.94). Beyond
//    ω·Δt ≈ 1.5 expect biased parameters; sample faster or use a particle method there.
//  * Sensor noise on a stiff potential (the paper's model, x⁹ walls, 2 % sensor noise, ω_max·Δt
//    0.5 and 1.0): the filtered x is uncertain by about the noise, and where the walls turn the
//    motion (|predicted x| 1.5–1.75 sd(x)) the Gaussian predictive variance is 2.0 ± 0.45 % too
//    small (mean squared standardised innovation at the truth 1.020; 1.004 ± 0.004 without
//    noise; elsewhere 1 within 0.5 %: bench/results/likelihood_innovations_paper.txt). The
//    likelihood makes up for it with a22's x² coefficient: the filter's score for 2Q at the
//    truth has mean +1.02 of its sd per 8 records × 1000 time units with noise (6.5 SEs from 0
//    over 40 seeds), +0.12 without, and 2Q comes out +5.7 ± 1.2 % (ω_max·Δt 1.0) and +5.0 ±
//    1.2 % (0.5) over 20 seeds, unbiased without noise. Not the substeps (4× changes the score
//    by 0.6 % of the bias), the block-start priors (8× the blocks: 2 %) or the data generator
//    (noisy − clean x: white, sd 0.9995 of the truth): bench/results/likelihood_score_paper10noise.txt.
//    The bias grows with the record length in SE units (a bias of the estimating equation, not
//    of a finite sample), so refine's simulation-based correction
//    (RefineOptions::bias_correction_datasets, detail/bias_correction.hpp) removes it there:
//    2Q −0.6 ± 1.4 % at ω_max·Δt 1.0 over 20 seeds, −0.2 ± 0.8 % with 4× the records
//    (bench/results/likelihood_corrected_*paper10noise.txt). At ω_max·Δt 0.5 the closure error
//    is smaller (mean squared innovation at the walls 1.0037 ± 0.0032) and the corrected 2Q is
//    +2.1 ± 1.1 % over 40 seeds (likelihood_corrected_paper05noise*.txt).
//  * The first samples of a block depend on data-based priors of the hidden states; with a
//    hidden state slower than the block (λ or 1/τ ≪ 1/length) those priors matter.
// Calibration of the resulting estimates (coverage of 95 % intervals over seeds):
// bench/results/likelihood_synthetic.txt.
//
// Start of a block: conditioned on its first sample, x ~ N(x_0, measurement_sd²); the hidden
// states get priors: y ~ N(0, 2·mean over the data of ((x_{k+1} − x_k)/Δt)²) (data-based, the
// same for every parameter value); with electromechanical_coupling or colored_noise (y, v, η)
// from the stationary law of the model linearised at x_0, given x_0 (detail/hidden_prior.hpp;
// where that law does not exist y as above, v ~ N(0, 2·Var(x)), η ~ N(0, intensity/2τ)) — a prior
// of v independent of x_0 biased the coupling by −4 SE at 288 records of 4000 samples, and η
// independent of y made the coupling's score z 19 on the true colored_noise model at 128
// records, both growing with the number of blocks. The first sample of a block is not scored.
//
// Records longer than `block_samples` are filtered as independent blocks (each conditioned on
// its first sample), so that long single records use both cores; blocks are fixed by the data,
// not by the thread count, so the result does not depend on it.
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/enum_names.hpp"
#include "vehs/core/dataset.hpp"
#include "vehs/core/fit_info.hpp"
#include "vehs/likelihood/observed_model.hpp"

namespace vehs::likelihood {

/// How the recorded input is applied between samples (detail/input_path.hpp): the enum of
/// vehs/core/fit_info.hpp, so that a model file carries it.
using vehs::InputInterpolation;
using vehs::kInputInterpolationNames;

struct FilterOptions {
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  /// RK4 substeps per sampling interval; 0: chosen from the start model's fastest linearised
  /// rate ρ over the central 99 % of the data's x (ρ·h ≤ 0.4, at least 2; at Δt = 0.7 on the
  /// bistable Duffing the estimates then move by < 0.02 SE against 20 substeps).
  int substeps = 0;
  /// Records longer than this are filtered in independent blocks of about this length.
  std::size_t block_samples = 1 << 14;
  int threads = 0;  ///< 0: the OpenMP default

  /// Empty when valid, else a one-line reason.
  std::string invalid_reason() const;
};

struct LikelihoodValue {
  double log_likelihood = 0.0;
  std::size_t observations = 0;  ///< scored samples (all but the first of each block)
  int substeps = 0;              ///< RK4 substeps per interval used
  std::size_t blocks = 0;
};

/// Log-likelihood of `data` (x, and u when the model has a drive term) under `model`.
/// Throws vehs::Error with one line for invalid options, a model the filter cannot take, data
/// that do not fit it (no or short drive, unequal sampling intervals) or a filter that diverges
/// (naming the record and sample).
LikelihoodValue log_likelihood(const ObservedModel& model, const Dataset& data,
                               const FilterOptions& options = {});

/// The filter's one-step predictions of every sample (the first sample of each block has its
/// own value and zero variance) and the filtered state after each update.
struct FilterTrace {
  std::vector<double> predicted_x, predicted_var;  ///< mean and variance of x_k | x_<k (incl. noise)
  std::vector<double> filtered_x, filtered_y;      ///< mean of x(t_k), y(t_k) | x_≤k
};
FilterTrace filter_trace(const ObservedModel& model, const Dataset& data,
                         const FilterOptions& options = {});

}  // namespace vehs::likelihood
