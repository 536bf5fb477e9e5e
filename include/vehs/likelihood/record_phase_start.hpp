#pragma once
// Starting values of a likelihood fit with one harmonic_forcing phase per record
// (RefineOptions::per_record_phase): a fit with one shared phase cannot see a forcing whose
// phase differs between records, so every record is fitted on its own.
#include <functional>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/likelihood/filter.hpp"
#include "vehs/likelihood/observed_model.hpp"

namespace vehs::likelihood {

/// A moment fit of one record's data (identify with the model's terms and harmonic_forcing).
using RecordFit = std::function<Model(const Dataset&)>;

/// Sets start.record_phases from `fit` of every record on its own (records whose own fit fails
/// (vehs::Error) or has no forcing keep the shared start), and the forcing's amplitude and omega
/// to the best-scoring candidate: the medians over the records, or a frequency several records
/// agree on with their median amplitude, each scored by the likelihood (`filter`) with every
/// record's phase scanned (a record's own fit of a weak forcing often lands on a noise peak; the
/// median of such frequencies is none of them). The phases are those of the best candidate's scan.
/// `start.model` must have a harmonic_forcing effect.
void start_record_phases(ObservedModel& start, const Dataset& data, const RecordFit& fit,
                         const FilterOptions& filter = {});

}  // namespace vehs::likelihood
