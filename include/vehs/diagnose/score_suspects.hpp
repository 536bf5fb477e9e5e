#pragma once
// Suspects from ALL the data by the likelihood (issue 13): for every catalogue effect the model
// lacks, a test of the model against the model plus the effect, from one pass of the
// continuous–discrete filter over the model's state (vehs/likelihood/score_test.hpp) at the
// model itself — no refit, no held-out split.
//
//  * term-like effects (coulomb_friction, quadratic_damping, nonlinear_damping,
//    asymmetric_stiffness, velocity_dependent_noise): the C(α) score test of the effect's
//    coefficients at 0, the model's own parameters projected out. One coefficient with a sign
//    (μ, c, q ≥ 0): one-sided z; several: χ² with their number of degrees of freedom. The
//    look-alikes quadratic_damping (y·|y|) and nonlinear_damping (its y³), whose scores correlate
//    ≈ 0.97 over a Gaussian-like velocity, are named with nearly equal z; when both are
//    significant, the model plus each one is refitted by the likelihood (vehs/likelihood/refine)
//    and the likelihood ratio of the two refits (one parameter each) ranks them. The preferred
//    form is named alone only when it adds significantly (one-sided, level alpha/10: the filter's approximation between two close forms grows with the data) to the other's
//    refit and the other adds nothing significant to its own; else the two are one group
//    ("damping that grows faster than linear", `not_resolved_from`), the preferred first, with
//    the multiple of the data that would resolve them with 90 % power (in each one's `test`).
//  * effects whose other parameters vanish under the null — impact_stop (gap),
//    electromechanical_coupling (λ), colored_noise (τ): the score test of k_stop, coupling,
//    intensity at 0 on a grid of the vanishing parameter (quantiles of |x|; multiples of the
//    data's typical frequency ω̄ = rms(ẋ)/rms(x)); the largest z over the grid, Bonferroni over
//    the grid points (conservative: neighbouring points are correlated).
//    These three, and the forcing below, are what tells a hidden state driven by noise
//    (colored_noise) from one driven by the velocity (electromechanical_coupling) from a
//    deterministic force: each is a likelihood of the filter over its own hidden state.
//    The two hidden states are look-alikes too (on a monostable potential at τ ≈ 1 their score
//    z's differ by < 1): when both are significant, the model plus each one is refitted by the
//    likelihood (every parameter free, started from the score tests' estimates) and the refits
//    (two parameters each) are ranked by 2ΔlogL. The better one is named alone only when 2ΔlogL
//    > 2 ln(grid/alpha): with the other true, 2ΔlogL is at most the likelihood ratio of the
//    model plus both against the true one, ≈ χ²₂ with its τ or λ scanned, so it names the wrong
//    one with probability ≤ grid · e^{−threshold/2} = alpha. Else the two are one group
//    ("a hidden state", `not_resolved_from`), the better one first.
//  In both groups `look_alikes` (on each member) says what was compared and the verdict.
//  * harmonic_forcing: a force a·cos(ωt + φ) moves the one-step predictions by a sinusoid at
//    ω, so the score of (a cos φ, a sin φ) at frequency ω is the Fourier coefficient of the
//    whitened innovations e_k/√S_k of the model's filter. With one phase for every record (in
//    absolute time): 2|Σ_r Σ_k w_k e^{−iωt_k}|²/N ~ χ²₂; with a phase per record (the
//    `harmonic_forcing_per_record` suspect): Σ_r 2|Σ_k w_k e^{−iωt_k}|²/n_r ~ χ²_{2R}
//    (the score of a² with the phases random). Scanned over the frequencies up to
//    `forcing_band`·ω̄ (twice oversampled), Bonferroni over the independent frequencies.
//    Fitted: ω̂ at the peak, the amplitude from the periodogram's excess.
// For every suspect: the statistic, its p-value after the scan, the z-equivalent Φ⁻¹(1 − p),
// the effect's parameters (one Fisher-scoring step from the null) with standard errors, the
// `add` fragment, and what the same test reaches under the model (the null: z-equivalent ≈ 0,
// claimed with probability α/effects) and under the refitted alternative (the power: the
// probability of a claim when the data come from the model plus the fitted effect, asymptotic
// for the score tests) — "not significant" with a high power means "absent", with a low power
// "too little data"; `detectable` is the effect size the test finds with 90 % power here.
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/core/user_effect.hpp"

namespace vehs::diagnose {

struct ScoreSuspectOptions {
  bool enabled = true;
  double alpha = 0.01;          ///< family-wise level of a claim (Bonferroni over the effects)
  int grid = 6;                 ///< points of the vanishing parameter's grid
  double forcing_band = 6.0;    ///< harmonic forcing scanned up to this multiple of ω̄
  double max_samples = 2.5e5;   ///< whole records, in order, up to this many samples, at least 2 (0: all)
  int threads = 0;              ///< 0: the OpenMP default
  /// A user's own effects, tested as the term-like ones are (their coefficients at 0: χ² with
  /// one degree of freedom per parameter; `add` is empty: the tools write their definition).
  std::vector<UserEffect> user_effects = {};
  std::function<void()> tested = {};  ///< called after each test (an effect, the term effects together, the forcing scans)
  std::string invalid_reason() const;
};

struct ScoreSuspect {
  std::string effect;           ///< catalogue name, or harmonic_forcing_per_record
  std::string test;             ///< one line: the statistic and its law
  double statistic = 0.0, dof = 1.0;
  int scanned = 1;              ///< points of the scan behind the p-value
  double p_value = 1.0;         ///< after the scan's correction (may underflow to 0: see log_p)
  double log_p = 0.0;           ///< its natural log, without underflow (the ranking)
  double z = 0.0;               ///< Φ⁻¹(1 − p) from log_p, ≥ 0 (0: no evidence at all)
  bool significant = false;     ///< p < alpha / tested effects
  std::map<std::string, double> params, params_stderr;
  std::string add;              ///< JSON fragment for the identify config
  double null_claim_rate = 0.0; ///< probability of a claim under the model (α / effects)
  double power = 0.0;           ///< probability of a claim under the fitted alternative
  std::string detectable;       ///< "mu >= 0.012" (90 % power), empty when not defined
  double seconds = 0.0;         ///< wall time of its filter passes (and half its look-alike group's refits)
  /// Look-alike effects these data do not tell apart from this one (named with it as one group;
  /// empty: none significant, or resolved — see `test`).
  std::vector<std::string> not_resolved_from;
  /// Present on the members of a look-alike group whose refits were compared (else empty).
  struct LookAlikes {
    std::vector<std::string> compared;  ///< the members, the one with the larger refit likelihood first
    std::vector<double> log_likelihoods;  ///< of the refits, in `compared`'s order
    double two_delta_log_l = 0.0;       ///< 2ΔlogL of the first's refit over the second's (≥ 0)
    bool resolved = false;              ///< the first is named alone
    double data_needed = 0.0;           ///< multiple of these data that resolves them with 90 % power (unresolved)
    std::string rule;                   ///< one line: what "resolved" means here
  };
  LookAlikes look_alikes;
};

struct ScoreSuspectReport {
  std::vector<ScoreSuspect> ranked;  ///< by log_p, then by statistic per degree of freedom
  std::vector<std::pair<std::string, std::string>> untested;
  std::size_t samples = 0, records = 0;
  double threshold = 0.0;  ///< per-effect p threshold (alpha / tested)
  /// How the filter applied the recorded input between samples: as the model was fitted
  /// (Model::fit->input), zero-order hold for a model without fit information.
  InputInterpolation input = InputInterpolation::ZeroOrderHold;
  std::string note;        ///< non-empty when the tests could not run at all
};

/// Runs the tests (see the header comment). `measurement_sd`: the white sensor noise on x the
/// model is observed with (0: none). Errors of single effects become `untested` entries; a
/// model the filter cannot take becomes `note`.
ScoreSuspectReport score_suspects(const Model& model, const Dataset& data, double measurement_sd,
                                  const ScoreSuspectOptions& options);

}  // namespace vehs::diagnose
