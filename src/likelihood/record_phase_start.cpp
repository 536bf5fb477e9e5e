#include "vehs/likelihood/record_phase_start.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "vehs/core/error.hpp"
#include "vehs/likelihood/detail/phase_scan.hpp"
#include "vehs/likelihood/signals.hpp"

namespace vehs::likelihood {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// One record's own forcing estimate.
struct RecordForcing {
  double omega, amplitude;
};

/// Candidate (omega, amplitude) starts: the medians, then the frequencies most records agree on
/// (the most other records within 3 %; a record's own fit of a weak forcing often lands on a
/// noise peak, and the median of such frequencies is none of them), each with the median
/// amplitude of the records that agree with it.
std::vector<RecordForcing> candidate_forcings(const std::vector<RecordForcing>& own, std::size_t max_candidates) {
  auto near = [](double a, double b) { return std::abs(a - b) <= 0.03 * std::abs(b); };
  std::vector<double> omegas, amplitudes;
  for (const auto& f : own) omegas.push_back(f.omega), amplitudes.push_back(f.amplitude);
  std::vector<RecordForcing> out{{median(omegas), median(amplitudes)}};
  std::vector<std::pair<int, std::size_t>> support;  // (records agreeing, record)
  for (std::size_t i = 0; i < own.size(); ++i) {
    int n = 0;
    for (const auto& f : own) n += near(f.omega, own[i].omega);
    support.push_back({n, i});
  }
  std::stable_sort(support.begin(), support.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [n, i] : support) {
    if (out.size() > max_candidates) break;
    if (n < 2) break;  // a frequency only its own record found
    const double w = own[i].omega;
    if (std::any_of(out.begin() + 1, out.end(), [&](const RecordForcing& c) { return near(c.omega, w); })) continue;
    std::vector<double> a;
    for (const auto& f : own)
      if (near(f.omega, w)) a.push_back(f.amplitude);
    out.push_back({w, median(a)});
  }
  return out;
}

}  // namespace

void start_record_phases(ObservedModel& start, const Dataset& data, const RecordFit& fit, const FilterOptions& filter) {
  Effect* h = nullptr;
  for (auto& e : start.model.effects)
    if (e.id == EffectId::HarmonicForcing) h = &e;
  if (!h) throw Error("per-record phases: the model has no harmonic_forcing effect");
  std::vector<RecordForcing> own;
  start.record_phases.assign(data.records.size(), h->params["phase"]);
  for (std::size_t r = 0; r < data.records.size() && fit; ++r) {
    try {
      const Model m = fit(slice_record(data, r, 0, data.records[r].size));
      const Effect* e = m.find_effect(EffectId::HarmonicForcing);
      if (!e) continue;
      start.record_phases[r] = e->params.at("phase");
      own.push_back({e->params.at("omega"), e->params.at("amplitude")});
    } catch (const Error&) {
      // keep the shared start for this record
    }
  }
  if (own.empty()) return;
  const std::vector<RecordForcing> candidates = candidate_forcings(own, 6);
  detail::FitChoice choice;
  choice.per_record_phase = true;
  choice.fit_measurement_noise = start.measurement_sd > 0.0;
  ObservedModel best = start;
  double best_value = -INFINITY;
  for (const RecordForcing& c : candidates) {  // each scored by the likelihood with its phases scanned
    ObservedModel trial = start;
    for (auto& e : trial.model.effects)
      if (e.id == EffectId::HarmonicForcing) e.params["omega"] = c.omega, e.params["amplitude"] = std::abs(c.amplitude);
    double value = -INFINITY;
    try {
      value = detail::scan_record_phases(trial, data, filter, choice);
    } catch (const Error&) {
      continue;  // e.g. the filter cannot take this start
    }
    if (value > best_value || candidates.size() == 1) best_value = value, best = std::move(trial);
  }
  if (best_value == -INFINITY) {  // no candidate could be scored: the medians, as before
    h->params["omega"] = candidates.front().omega;
    h->params["amplitude"] = candidates.front().amplitude;
    return;
  }
  start = std::move(best);
}

}  // namespace vehs::likelihood
