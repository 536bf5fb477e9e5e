#pragma once
// The incidental-parameter bias of harmonic_forcing's shared amplitude when every record has its
// own free phase (RefineOptions::per_record_phase).
//
// With the phase φ_r of record r estimated, the model's forcing in that record is the true one
// turned by δφ_r = φ̂_r − φ_r, whose projection on the truth is A·cos δφ_r ≈ A(1 − δφ_r²/2); the
// maximum compensates: E[Â] ≈ A(1 + h/2), h the harmonic mean over records of Var(φ̂_r) — the
// Rice bias of an amplitude measured with an unknown phase, ≈ R·SE/(2A) standard errors for R
// records of equal information. refine() returns Â·(1 − h/2) (first order; it under-corrects when
// a record's own signal-to-noise A/(√R·SE) is below about 2).
//
// Measured (bench/bench_record_phase_bias.cpp, bench/results/record_phase_bias.txt: bistable
// Duffing, A 0.12 at ω 0.8, Δt 0.35, ≈ 64 000 samples, fits from the truth with the true phases
// held against free): the shift free − held is 0.043 ± 0.010, 0.128 ± 0.008 and 0.514 ± 0.020 SE
// at R = 4, 16 and 64 records (predicted 0.033, 0.133, 0.527); after the correction −0.010 ±
// 0.010, −0.014 ± 0.008 and +0.017 ± 0.020. With the phases held the amplitude's mean z is
// −0.07 ± 0.14 (R 16, 40 seeds): the maximum is otherwise unbiased.
#include "vehs/likelihood/refine.hpp"

namespace vehs::likelihood::detail {

/// The factor 1 − h/2 (1 when `res` has no record phases or no amplitude; h from res.covariance).
double record_phase_amplitude_factor(const Result& res);

/// Multiplies the amplitude's value, model entry and standard error by that factor (its
/// covariance row and column too); returns the factor.
double correct_record_phase_bias(Result& res);

}  // namespace vehs::likelihood::detail
