#pragma once
// The per-record phase scan of harmonic_forcing with one phase per record (refine() and the
// start of such a fit, record_phase_start.hpp).
#include "vehs/core/dataset.hpp"
#include "vehs/likelihood/detail/parameterization.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/observed_model.hpp"

namespace vehs::likelihood::detail {

/// The likelihood is periodic in every phase with side optima, and the optimiser is local:
/// every record's phase is set to the best of 12 equally spaced values around its given start
/// (the given start included), the shared parameters held at their start values. Records are
/// independent given the shared parameters, so one filter pass per grid value scores every
/// record at once. Returns the log-likelihood at the phases chosen (−∞ when no pass succeeded).
double scan_record_phases(ObservedModel& start, const Dataset& data, const FilterOptions& filter,
                          const FitChoice& choice);

}  // namespace vehs::likelihood::detail
