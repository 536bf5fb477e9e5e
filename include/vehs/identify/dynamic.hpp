#pragma once
// Identification of the dynamic effects of the catalogue (contracts.md §4): forces that are not
// per-sample functions of (x, y, u) — impact stops with unknown gaps, harmonic forcing of unknown
// frequency, an electromechanical hidden state of unknown time constant.
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
// colored_noise is not identified yet (the drift residuals become an ARMA process whose
// innovation filter must be estimated jointly; see data/identify/README.md).
#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/identify/identify.hpp"
#include "vehs/io/measurements.hpp"

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

namespace detail {
/// identify() with dynamic effects in options.effects (called by identify()).
Result identify_dynamic(const Dataset& data, const Options& options);
}  // namespace detail

}  // namespace vehs::identify
