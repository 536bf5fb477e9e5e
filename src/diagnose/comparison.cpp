// The statistics of a diagnosis: the same per-unit statistics of the data and of the model's
// twins (records simulated like the data), with progress reports.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/quantisation.hpp"

namespace vehs::diagnose::detail {

namespace {

/// The per-unit statistics of dataset d (the data or a twin), in parallel over units; with `add`
/// summed into `out` (twins over replicates), else replacing it.
void unit_statistics(const Comparison& cmp, const Dataset& d, std::vector<UnitStats>& out, bool add,
                     vehs::detail::ProgressCounter& prog) {
  const std::vector<UnitSpan>& units = cmp.plan.units;
  const Dataset& data = cmp.data;
  std::vector<UnitStats> one(units.size());
  std::exception_ptr failure;
  std::mutex mtx;
#pragma omp parallel for schedule(dynamic, 1)
  for (long j = 0; j < static_cast<long>(units.size()); ++j) {
    try {
      const UnitSpan& s = units[static_cast<std::size_t>(j)];
      const Record& rec = d.records[s.record];
      // the drive is the data's (twins are driven by it; their datasets need not carry it)
      compute_unit(cmp.setup, d.x_of(rec), cmp.model.uses_drive() ? data.u_of(data.records[s.record]) : nullptr,
                   rec.size, cmp.forcing_t0[s.record], s, one[static_cast<std::size_t>(j)]);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mtx);
      if (!failure) failure = std::current_exception();
    }
    prog.advance();
  }
  if (failure) std::rethrow_exception(failure);
  if (!add) {
    out = std::move(one);
  } else {
    for (std::size_t j = 0; j < units.size(); ++j) out[j].add(one[j]);
  }
}

/// How the twins are simulated: the paper's scheme at the recorded step for scheme-consistent
/// data, else Itô–Taylor 1.5 on fine substeps (continuous_twin_substeps: at least 10, more at
/// coarse sampling); the lens's sensor noise and smoothing.
TwinSettings choose_twin_settings(const Comparison& cmp, SamplingVerdict verdict) {
  const Options& opt = cmp.options;
  const Lens& lens = cmp.lens;
  const StatsSetup& box = cmp.setup;
  TwinSettings ts;
  const bool consistent = verdict == SamplingVerdict::SchemeConsistent;
  ts.scheme = opt.twin_scheme_auto ? (consistent ? sim::Scheme::Rk4Euler : sim::Scheme::Taylor15) : opt.twin_scheme;
  ts.substeps = opt.twin_substeps > 0 ? opt.twin_substeps
                : consistent        ? 1
                                    : continuous_twin_substeps(cmp.model, lens.dt, box.x_lo, box.x_hi, box.v_lo, box.v_hi);
  ts.sensor_noise = lens.sensor_noise_sd;
  if (const Quantisation q = find_quantisation(cmp.data); q.quantised()) {
    ts.quantisation_step = q.step;
    ts.sensor_noise = std::sqrt(std::max(lens.sensor_noise_sd * lens.sensor_noise_sd - q.noise_variance(), 0.0));
  }
  ts.input = cmp.model.fit ? cmp.model.fit->input : InputInterpolation::ZeroOrderHold;
  ts.seed = opt.seed;
  ts.smoothing = lens.sensor_noise_sd > 0.0 ? std::max(2, lens.stride) : 1;
  return ts;
}

/// Replicate rep's own pooled histograms p(x), p(x, v̂) (the twin-vs-twin Hellinger reference):
/// the running sums after it minus those after replicate 0.
void keep_replicate_histograms(Comparison& cmp, int rep) {
  const StatsSetup& setup = cmp.setup;
  std::vector<double> hx(static_cast<std::size_t>(setup.hx_n), 0.0);
  std::vector<double> hxy(static_cast<std::size_t>(setup.hxy_nx * setup.hxy_nv), 0.0);
  for (std::size_t j = 0; j < cmp.twin_stats.size(); ++j) {
    const UnitStats& t = cmp.twin_stats[j];
    for (std::size_t b = 0; b < hx.size(); ++b) hx[b] += t.hx[b] - (rep == 1 ? cmp.twin_rep0[j].hx[b] : 0.0);
    for (std::size_t b = 0; b < hxy.size(); ++b) hxy[b] += t.hxy[b] - (rep == 1 ? cmp.twin_rep0[j].hxy[b] : 0.0);
  }
  cmp.rep_hx.push_back(std::move(hx));
  cmp.rep_hxy.push_back(std::move(hxy));
}

}  // namespace

void compute_statistics(Comparison& cmp, SamplingVerdict verdict, Result& res, Stopwatch& watch) {
  const Options& opt = cmp.options;
  const std::size_t U = cmp.plan.units.size();
  SamplingInfo& si = res.sampling;
  const int R = cmp.replicates = opt.replicates > 0
                    ? opt.replicates
                    : std::clamp(static_cast<int>(std::ceil(2e6 / static_cast<double>(std::max<std::size_t>(res.samples, 1)))), 1, 8);
  si.replicates = R;
  vehs::detail::ProgressCounter prog(opt.progress, "diagnose", static_cast<long long>(U) * (R + 1));
  unit_statistics(cmp, cmp.data, cmp.data_stats, false, prog);
  watch.lap(res, "data_statistics");

  cmp.twin_settings = choose_twin_settings(cmp, verdict);
  si.twin_scheme = cmp.twin_settings.scheme;
  si.twin_substeps = cmp.twin_settings.substeps;
  TwinSimulator twins(cmp.model, cmp.data, cmp.twin_settings);
  cmp.twin_stats.resize(U);
  for (auto& t : cmp.twin_stats) t.init(cmp.setup);
  double sim_seconds = 0.0;
  Dataset twin;
  for (int rep = 0; rep < R; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    twins.simulate(rep, twin);
    sim_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    unit_statistics(cmp, twin, cmp.twin_stats, true, prog);
    if (rep == 0) cmp.twin_rep0 = cmp.twin_stats;
    if (rep < 2) keep_replicate_histograms(cmp, rep);
  }
  prog.finish();
  res.timings.emplace_back("twin_simulation", sim_seconds);
  watch.lap(res, "twin_statistics");

  double invalid = 0.0;
  for (const auto& s : cmp.data_stats) invalid += s.invalid_rows;
  if (invalid > 0)
    res.warnings.push_back(fmt(invalid, 6) + " data rows where the model's residual variance is not positive were left out");
}

}  // namespace vehs::diagnose::detail
