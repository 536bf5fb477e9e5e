#pragma once
// harmonic_forcing with one phase per record (a likelihood fit with `per_record_phase`: records
// started at unrelated times). The phases live in the model's fit (FitInfo::likelihood
// record_phases) and belong to the records the model was fitted to, in their order; every tool
// that evaluates or simulates such a model on those records uses record r's phase for record r.
#include <cstddef>
#include <string>
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs {

/// The model's phase per record (empty: one shared phase, or no harmonic_forcing).
const std::vector<double>& record_phases_of(const Model& model);

/// The phases of the first `records` records the model was fitted to (empty when the phase is
/// shared). Throws vehs::Error naming `where` when the model has fewer phases than records.
std::vector<double> leading_record_phases(const Model& model, std::size_t records, const std::string& where);

/// Per record of `data` (the records the model was fitted to, or their leading ones), the time origin τ_r at which the model's shared-phase forcing
/// a·cos(ω·(τ_r + k·dt) + φ) equals record r's own a·cos(ω·(t0_r + k·dt) + φ_r): τ_r = t0_r +
/// (φ_r − φ)/ω with per-record phases, else t0_r. Throws vehs::Error naming `where` when the
/// model has phases for fewer records than the data, or (`exact`) for another number.
std::vector<double> forcing_time_origins(const Model& model, const Dataset& data, const std::string& where,
                                         bool exact = false);

}  // namespace vehs
