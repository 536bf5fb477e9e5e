#include "vehs/likelihood/record_phase_start.hpp"

#include <algorithm>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::likelihood {

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
}  // namespace

void start_record_phases(ObservedModel& start, const Dataset& data, const RecordFit& fit) {
  Effect* h = nullptr;
  for (auto& e : start.model.effects)
    if (e.id == EffectId::HarmonicForcing) h = &e;
  if (!h) throw Error("per-record phases: the model has no harmonic_forcing effect");
  std::vector<double> amplitudes, omegas;
  start.record_phases.assign(data.records.size(), h->params["phase"]);
  for (std::size_t r = 0; r < data.records.size() && fit; ++r) {
    try {
      const Model m = fit(slice_record(data, r, 0, data.records[r].size));
      const Effect* e = m.find_effect(EffectId::HarmonicForcing);
      if (!e) continue;
      start.record_phases[r] = e->params.at("phase");
      amplitudes.push_back(e->params.at("amplitude"));
      omegas.push_back(e->params.at("omega"));
    } catch (const Error&) {
      // keep the shared start for this record
    }
  }
  if (!amplitudes.empty()) {
    h->params["amplitude"] = median(amplitudes);
    h->params["omega"] = median(omegas);
  }
}

}  // namespace vehs::likelihood
