// The statistics of a diagnosis: the same per-unit statistics of the data and of the model's
// twins (records simulated like the data), with progress reports.
#include <algorithm>
#include <cmath>
#include <exception>
#include <mutex>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/core/detail/progress_counter.hpp"

namespace vehs::diagnose::detail {

void compute_statistics(Comparison& cmp, SamplingVerdict verdict, Result& res, Stopwatch& watch) {
  const Model& model = cmp.model;
  const Dataset& data = cmp.data;
  const Options& opt = cmp.options;
  const Lens& lens = cmp.lens;
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitSpan>& units = cmp.plan.units;
  SamplingInfo& si = res.sampling;
  // ---- statistics of the data and of the twins, per unit
  auto run_units = [&](const Dataset& d, std::vector<UnitStats>& out, bool add, vehs::detail::ProgressCounter& prog) {
    std::vector<UnitStats> one(units.size());
    std::exception_ptr failure;
    std::mutex mtx;
#pragma omp parallel for schedule(dynamic, 1)
    for (long j = 0; j < static_cast<long>(units.size()); ++j) {
      try {
        const UnitSpan& s = units[static_cast<std::size_t>(j)];
        const Record& rec = d.records[s.record];
        // the drive is the data's (twins are driven by it; their datasets need not carry it)
        compute_unit(setup, d.x_of(rec), model.uses_drive() ? data.u_of(data.records[s.record]) : nullptr,
                             rec.size, rec.t0, s, one[static_cast<std::size_t>(j)]);
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
  };
  const int R = cmp.replicates = opt.replicates > 0
                    ? opt.replicates
                    : std::clamp(static_cast<int>(std::ceil(2e6 / static_cast<double>(std::max<std::size_t>(res.samples, 1)))), 1, 8);
  si.replicates = R;
  vehs::detail::ProgressCounter prog(opt.progress, "diagnose", static_cast<long long>(units.size()) * (R + 1));
  std::vector<UnitStats>& dstats = cmp.data_stats;
  std::vector<UnitStats>& tstats = cmp.twin_stats;
  std::vector<UnitStats>& rep0 = cmp.twin_rep0;
  run_units(data, dstats, false, prog);
  watch.lap(res, "data_statistics");

  TwinSettings& ts = cmp.twin_settings;
  {
    const bool consistent = verdict == SamplingVerdict::SchemeConsistent;
    ts.scheme = opt.twin_scheme_auto ? (consistent ? sim::Scheme::Rk4Euler : sim::Scheme::Taylor15) : opt.twin_scheme;
    ts.substeps = opt.twin_substeps > 0 ? opt.twin_substeps : (consistent ? 1 : 10);
    ts.sensor_noise = lens.sensor_noise_sd;
    ts.seed = opt.seed;
    ts.smoothing = lens.sensor_noise_sd > 0.0 ? std::max(2, lens.stride) : 1;
    si.twin_scheme = ts.scheme;
    si.twin_substeps = ts.substeps;
  }
  TwinSimulator twins(model, data, ts);
  tstats.resize(units.size());
  for (auto& t : tstats) t.init(setup);
  std::vector<std::vector<double>>& rep_hx = cmp.rep_hx;  // pooled per replicate (Hellinger null)
  std::vector<std::vector<double>>& rep_hxy = cmp.rep_hxy;
  double sim_seconds = 0.0;
  {
    Dataset twin;
    for (int rep = 0; rep < R; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      twins.simulate(rep, twin);
      sim_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      run_units(twin, tstats, true, prog);
      if (rep == 0) rep0 = tstats;
      if (rep < 2) {
        std::vector<double> hx(static_cast<std::size_t>(setup.hx_n), 0.0), hxy(static_cast<std::size_t>(setup.hxy_nx * setup.hxy_nv), 0.0);
        for (std::size_t j = 0; j < units.size(); ++j) {
          for (std::size_t b = 0; b < hx.size(); ++b) hx[b] += tstats[j].hx[b] - (rep == 1 ? rep0[j].hx[b] : 0.0);
          for (std::size_t b = 0; b < hxy.size(); ++b) hxy[b] += tstats[j].hxy[b] - (rep == 1 ? rep0[j].hxy[b] : 0.0);
        }
        rep_hx.push_back(std::move(hx));
        rep_hxy.push_back(std::move(hxy));
      }
    }
  }
  prog.finish();
  res.timings.emplace_back("twin_simulation", sim_seconds);
  watch.lap(res, "twin_statistics");

  double invalid = 0.0;
  for (const auto& s : dstats) invalid += s.invalid_rows;
  if (invalid > 0)
    res.warnings.push_back(fmt(invalid, 6) + " data rows where the model's residual variance is not positive were left out");
}

}  // namespace vehs::diagnose::detail
