#pragma once
// Starts of a fit with electromechanical_coupling across the time scales of its hidden state.
//
// Why. The likelihood in (coupling κ, λ) has a ridge: with λ far below the oscillation's
// frequency ω the term −κv acts as a stiffness κ, far above it as a damping κ/λ, so drift terms
// trade with it and a local optimiser follows the ridge from wherever it starts. From identify's
// moment start a 4-record linear oscillator (κ 0.3, λ 1, 16 000 samples) was fitted at
// κ 0.06 ± 0.07, λ 0.008 ± 0.01 — a local maximum 3.6 SE from the truth and 4.7 below the
// log-likelihood at the truth with the drift held at the truth.
#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/detail/parameterization.hpp"
#include "vehs/likelihood/observed_model.hpp"
#include "vehs/likelihood/refine.hpp"

namespace vehs::likelihood::detail {

/// The fitted model from the best of three starts, `start` and two others — λ at 0.1 and 1 times
/// the data's ω (ω² = mean (Δx/Δt)² / Var x), κ at max(κ_start, 0.1 ω²), everything else as
/// given — whose maximum-likelihood fit (on a share of about 4·warm_start_samples samples of
/// larger data, warm_start_share) reaches the highest likelihood; `start` itself when the model
/// has no electromechanical_coupling or κ or λ is held fixed (then nothing is fitted here).
/// Starts whose fit fails are skipped. On that 4-record case the three fits reach log L 42309.1
/// (the moment start: κ 1.07, λ 2e-8), 42309.9 (λ 0.1ω) and 42316.5 (λ ω: κ 1.5 ± 2.0,
/// λ 4.2 ± 3.5, the truth within about 1 SE); a start at 3ω or 10ω (tried with a temporary
/// build) reaches 0.3 higher along the same ridge (κ 33, λ 29) at up to 10× the cost on
/// Silverbox (the filter's substeps follow λ), so they are not tried.
ObservedModel best_hidden_state_start(const ObservedModel& start, const Dataset& data,
                                      const RefineOptions& o, const FitChoice& choice);

}  // namespace vehs::likelihood::detail
