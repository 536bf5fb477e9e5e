#pragma once
// Identification of the dynamic effects of the catalogue (docs/model-file.md#effects): forces that are not
// per-sample functions of (x, y, u) — impact stops with unknown gaps, harmonic forcing of unknown
// frequency, an electromechanical hidden state of unknown time constant, an Ornstein–Uhlenbeck
// (coloured) excitation.
//
// Model. b2 = Σ c_j φ_j(x, y, u) + Σ_e f_e(t, x-history; θ_e, β_e), where every dynamic force
// is linear in its "linear" parameters β_e for fixed "nonlinear" parameters θ_e:
//  * harmonic_forcing:  f = A cos(ωt) + B sin(ωt)   (θ = ω; β = (A, B);
//                        amplitude = √(A² + B²), phase = atan2(−B, A), so f = amplitude·cos(ωt + phase));
//                        t is the absolute time of the sample (record t0 + i·Δt).
//  * impact_stop:       f = k_stop·[−(x − gap)⁺ + (−x − gap_neg)⁺]   (θ = (gap, gap_neg); β = k_stop).
//                        With central kinematics the regressor is this shape averaged over the
//                        tent kernel of the second difference (x linear between samples): the
//                        ULI acceleration is the tent average of ẍ, and the average of a kinked
//                        force is not the force at the average (Jensen); without it the gap
//                        comes out low by about |y|·h/4 and k_stop a few % low.
//  * electromechanical_coupling: f = −coupling·v, v the velocity filtered by dv = (y − λv) dt
//                        (θ = λ; β = coupling). v is computed from the displacement itself:
//                        v_{i+1} = e^{−λΔt} v_i + (x_{i+1} − x_i)(1 − e^{−λΔt})/(λΔt), exact for x
//                        linear over each interval, v = 0 at the first sample of every record (as
//                        the simulator starts it; on real data a transient of duration ~1/λ).
// Parameters given by the user are held fixed (a fixed linear parameter turns its force into a
// known offset of the target). harmonic_forcing: amplitude can only be fixed together with phase.
//
// Fit (profile least squares on the identify contrast). For fixed θ the drift is linear in
// (c, β): the Itô-corrected normal equations of identify (ULI: G z = Σ ζ â − ½ Σ a22 ∂_vζ, with
// ζ = [φ, dynamic columns]; the filtered velocity of the electromechanical state shares the noise
// of the last half window with â: Cov(v, ε) = a22·J(λ, h), J = [h²/2 − h/λ + (1 − e^{−λh})/λ²]/(λh²),
// subtracted like the Itô term — without it the profile runs to large λ, where −v ≈ −y/λ + â/λ²
// regresses â on its own noise)
// give the profile contrast C(θ) = Σ â² − bᵀG⁻¹b. θ is found by a grid (ω: the largest lines of
// the Welch spectrum of the baseline residuals, then a scan at a quarter of the record's
// frequency resolution; gaps: quantiles of x; λ: a log grid from 1/(record duration) to 1/(2h))
// and golden-section refinement (coordinate-wise when there are two). The baseline support is the
// one identify selects; after the fit the dynamic force is subtracted from the target and
// identify runs again (selection, diffusion, sampling diagnosis on the corrected target); when the
// selected support or estimator changes the profile fit is repeated once.
//
// Standard errors: sandwich of the joint estimating equations of (c, β, θ) — scores
// ζ r − ito and g r with g = ∂f/∂θ (central finite differences), J = Σ [ζ; g][ζ; g]ᵀ, Ω the
// covariance of score sums over contiguous batches — J⁻¹ΩJ⁻ᵀ; amplitude and phase by the delta
// method. The uncertainty of the diffusion estimate in the Itô correction is not propagated here.
//
// Identifiability (reported in the model file as "dynamic_fit"): harmonic forcing needs a line
// above the residual background; impact stops need samples beyond the gap (the count is
// reported); electromechanical coupling is identifiable only for λ comparable to the oscillation
// frequencies: for λ ≫ ω the force is −(coupling/λ)·y (damping), for λ ≪ ω it tends to
// −coupling·∫y (stiffness), and the profile is flat — the fitted λ then has a large standard error.
//
// colored_noise (identify_colored; not combinable with the other dynamic effects yet). Model:
// ẍ = b2(x, y) + η + √a22·ξ, dη = −η/τ dt + √intensity/τ dW (Itô; Var η = σ² = intensity/(2τ),
// Corr η(s) = e^{−|s|/τ}; white noise of a22 = intensity as τ → 0). Central (ULI) kinematics at
// stride k, h = kΔt, clean displacement (the `uli` estimator is used: the sampling diagnosis would
// read the OU's positive lag-2k residual autocorrelation as sensor noise). The drift residual
// r_i = â_i − b2(x_i, v̂_i) = η̄_i + ε_i, η̄ the tent average of η over [t_i − h, t_i + h] and ε the
// ULI noise, which is uncorrelated beyond lag 2k−1 samples. So for lags L ≥ 2k (tent kernels
// disjoint) Cov(r_i, r_{i+L}) = σ²·M²·e^{−LΔt/τ}, M = 2(cosh(h/τ) − 1)/(h/τ)² (→ 1), and
//  1. tau, intensity: least squares of the residual autocovariance C(L) = A e^{−LΔt/τ} over
//     L ∈ [2k, L₁] (L₁: where C falls below 5 % of C(2k)); A in closed form, τ by golden section
//     in log τ; intensity = 2τA/M². Given params are held fixed.
//  2. drift (GLS by prediction errors): least squares alone is biased (η drives y, so E[y η] ≠ 0:
//     measured β −0.054 for a true −0.1). A Kalman filter of η (AR(1) with φ = e^{−Δt/τ}, observed
//     through r with the long-run variance a22/Δt of the ULI noise) predicts η̄_i from rows
//     ≤ i − 2k; the prediction is linear in the residuals, hence in the drift coefficients, so the
//     same filter run on â and on every dictionary column gives T_i = â_i − η̂(â)_i and
//     Z_i = ζ_i − η̂(ζ)_i, and G c = Σ Z T − Σ (½ a22 + 2h·P_pred) ∂_vζ: the usual Itô correction
//     (the filtered columns use only samples before the noise of â_i) plus Cov(v̂_i, e_i) ≈
//     2h·P_pred — v̂_i carries η over [t_{i−k}, t_{i+k}], which the prediction from row i − 2k
//     does not see (P_pred the filter's prediction-error variance). The prediction error is
//     otherwise orthogonal to the past of x when the predictor is the conditional mean; the MA(1)
//     noise is treated as white with its long-run variance in the filter (suboptimal).
//  3. white diffusion: E[r_i²] = σ²·Q + (2/3)·a22(x_i, v̂_i)/h, Q the tent self-average of the
//     OU correlation (quadrature); least squares of (3h/2)(r² − σ²Q) on the diffusion library.
//  Steps 1–3 are iterated (≤ 6 rounds, until τ and the drift change by < 0.1 %).
// Standard errors: tau and intensity by a delete-one-batch jackknife of the autocovariance fit
// (≥ 20 contiguous batches; drift held at its estimate — its uncertainty is not propagated);
// drift by the batch sandwich of the GLS estimating equations; diffusion by a batch sandwich.
// Measured on 20 simulated data sets (τ ∈ [0.2, 1], intensity ∈ [0.02, 0.06], two potentials,
// 8 × 400 s): |z| ≤ 1.84 for τ, ≤ 1.37 for intensity, drift and diffusion terms within 2.64 SE
// in 19 of 20 (one damping at 3.44). Known weakness: with short τ and a strong excitation
// (τ = 0.25, intensity ≈ 2·a22) the intensity under-covers (3 of 16 below z = −2.3, down to
// −3.35) — see docs/studies/dynamic-effects.md.
// Not handled: sensor noise (noisy estimator), forward kinematics, combination with stops /
// forcing / electromechanical coupling, held-fixed params of term-like effects.
#include <cstddef>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::identify {

/// True for effects that are not plain dictionary terms.
bool is_dynamic(EffectId id);
/// True for dynamic effects identify can fit.
bool dynamic_fit_supported(EffectId id);

/// The force the dynamic effects (with complete params) add to b2 at every sample of record
/// `r` (colored_noise, a random excitation, adds nothing). `out` receives r.size values.
/// tent_k > 0: the stop force is averaged over the kernel of the central second difference at
/// stride tent_k (x linear between samples) — what the ULI acceleration sees of a force with a
/// kink; the smooth forces are taken at the sample (their kernel average differs by
/// O((ωh)²/12)).
void dynamic_force(const std::vector<Effect>& effects, const Dataset& data, const Record& r,
                   std::vector<double>& out, int tent_k = 0);

/// Filtered velocity of electromechanical_coupling along a record (see the header comment).
void filtered_velocity(const double* x, std::size_t n, double dt, double lambda, double* v);

/// One-step-ahead prediction of the OU excitation of colored_noise along a record (central
/// kinematics at stride k): a Kalman filter of the AR(1) state η (φ = e^{−Δt/τ}, stationary
/// variance intensity/(2τ)) observed through the drift residuals r_i = â_i − b2(x_i, v̂_i) with
/// observation variance a22(x_i, v̂_i)/Δt (the long-run variance of the ULI noise per row, the
/// filter averaging over many rows), the same filter as the GLS drift fit; eta_pred[i] = e^{−2h/τ}·(filtered η at
/// row i − 2k), which uses the displacement up to sample i − k only (independent of the noise of
/// â_i). Rows without a prediction get 0.
void colored_prediction(const Effect& colored, const TermList& drift, const TermList& diffusion,
                        const double* x, const double* u, std::size_t n, double dt, int k,
                        std::vector<double>& eta_pred);

}  // namespace vehs::identify
