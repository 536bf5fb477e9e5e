#include "vehs/likelihood/record_phase_start.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include <unsupported/Eigen/FFT>

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

/// The frequencies (rad per time unit) of the `count` strongest narrow lines in the records'
/// summed periodogram of x: each record's mean removed, Hann-windowed and zero-padded to a common
/// length (4× the longest record), |X|² summed over the records (their phases differ, so powers
/// add), each bin divided by the median of the 64 bins around it (the broadband response), the
/// local maxima of that ratio ranked. A forcing no single record resolves shows as a line once the
/// records are summed. Each record's first 2^18 samples at most: the buffers stay under 40 MB,
/// and a record that long resolves a forcing in its own fit. Empty when the records do not share
/// one sampling interval. (core's welch_spectrum, without the zero-padding, put the line up to
/// half a bin off: the start then missed in 3 of 60 seed shifts of test_record_phase_start.cpp.)
std::vector<double> spectral_lines(const Dataset& data, std::size_t count) {
  constexpr std::size_t kMaxSamples = std::size_t(1) << 18;
  const double dt = data.records.front().dt;
  std::size_t longest = 0;
  for (const auto& r : data.records) {
    if (r.dt != dt) return {};
    longest = std::max(longest, std::min(r.size, kMaxSamples));
  }
  std::size_t L = 1;
  while (L < 4 * longest) L *= 2;
  const std::size_t half = L / 2;
  std::vector<double> power(half + 1, 0.0), buf(L);
  std::vector<std::complex<double>> spec;
  Eigen::FFT<double> fft;
  for (const auto& r : data.records) {
    const std::size_t n = std::min(r.size, kMaxSamples);
    if (n < 16) continue;
    const double* x = data.x_of(r);
    double mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) mean += x[i];
    mean /= double(n);
    std::fill(buf.begin(), buf.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i)
      buf[i] = (x[i] - mean) * (0.5 - 0.5 * std::cos(2.0 * M_PI * double(i) / double(n - 1)));
    fft.fwd(spec, buf);
    for (std::size_t k = 0; k <= half; ++k) power[k] += std::norm(spec[k]);
  }
  const std::size_t w = 32, lobe = 2 * L / longest + 1;  // the window's main lobe in bins
  std::vector<std::pair<double, std::size_t>> peaks;
  std::vector<double> around;
  for (std::size_t k = std::max(w, 2 * lobe); k + w <= half; ++k) {
    if (!(power[k] >= power[k - 1] && power[k] > power[k + 1])) continue;
    around.assign(power.begin() + long(k - w), power.begin() + long(k + w));
    std::nth_element(around.begin(), around.begin() + long(w), around.end());
    if (around[w] > 0.0) peaks.push_back({power[k] / around[w], k});
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<double> out;
  for (std::size_t i = 0; i < peaks.size() && out.size() < count; ++i)
    out.push_back(2.0 * M_PI * double(peaks[i].second) / (double(L) * dt));
  return out;
}

/// Candidate (omega, amplitude) starts, at most 1 + max_candidates: the medians alone when at
/// least half the records' own frequencies are within 3 % of theirs; else the medians, the summed
/// periodogram's lines (with the median amplitude), then the records' own frequencies, those
/// most records agree on (within 3 %) first — a record's own fit of a weak forcing often lands on
/// a noise peak, and the median of such frequencies is none of them; on 16 records the truth's
/// was sometimes found by one record only — each with the median amplitude of the records that
/// agree with it.
std::vector<RecordForcing> candidate_forcings(const std::vector<RecordForcing>& own, const std::vector<double>& lines,
                                             std::size_t max_candidates) {
  auto near = [](double a, double b) { return std::abs(a - b) <= 0.03 * std::abs(b); };
  std::vector<double> omegas, amplitudes;
  for (const auto& f : own) omegas.push_back(f.omega), amplitudes.push_back(f.amplitude);
  std::vector<RecordForcing> out{{median(omegas), median(amplitudes)}};
  const auto agree = std::count_if(own.begin(), own.end(), [&](const RecordForcing& f) { return near(f.omega, out[0].omega); });
  if (2 * std::size_t(agree) >= own.size()) return out;  // most records resolve it alone: nothing to choose
  for (double w : lines)
    if (out.size() <= max_candidates && std::none_of(out.begin(), out.end(), [&](const RecordForcing& c) { return near(c.omega, w); }))
      out.push_back({w, median(amplitudes)});
  std::vector<std::pair<int, std::size_t>> support;  // (records agreeing, record)
  for (std::size_t i = 0; i < own.size(); ++i) {
    int n = 0;
    for (const auto& f : own) n += near(f.omega, own[i].omega);
    support.push_back({n, i});
  }
  std::stable_sort(support.begin(), support.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [n, i] : support) {
    if (out.size() > max_candidates) break;
    const double w = own[i].omega;
    if (std::any_of(out.begin(), out.end(), [&](const RecordForcing& c) { return near(c.omega, w); })) continue;
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
  const std::vector<RecordForcing> candidates = candidate_forcings(own, spectral_lines(data, 6), 12);
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
