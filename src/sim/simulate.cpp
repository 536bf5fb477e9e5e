// The simulator's public entry points: checks, set-up of the engine, statistics.
#include "vehs/sim/simulate.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "engine.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/parallel.hpp"
#include "vehs/core/detail/memory.hpp"
#include "vehs/core/diffusion_domain.hpp"
#include "vehs/core/error.hpp"
#include "vehs/sim/simd.hpp"

namespace vehs::sim {

using detail::CompiledModel;
using detail::XPolynomial;

namespace {

std::string num(double v) { return vehs::detail::format_number(v, 6); }

bool all_finite(const std::vector<double>& v) {
  for (double d : v)
    if (!std::isfinite(d)) return false;
  return true;
}

double largest_magnitude(const std::vector<double>& v) {
  double m = 0.0;
  for (double d : v) m = std::max(m, std::abs(d));
  return m;
}

}  // namespace

std::string SimulationOptions::invalid_reason() const {
  if (!(dt > 0.0) || !std::isfinite(dt)) return "dt must be > 0 (got " + num(dt) + ")";
  if (substeps < 1) return "substeps must be >= 1 (got " + std::to_string(substeps) + ")";
  if (samples < 2) return "a record needs at least 2 samples (duration >= 2·dt)";
  if (records < 1) return "records must be >= 1 (got " + std::to_string(records) + ")";
  if (first_record + static_cast<std::uint64_t>(records) > (std::uint64_t{1} << 32))
    return "record ids (first_record + records) must stay below 2^32";
  if (x0.uniform) {
    if (!std::isfinite(x0.lo) || !std::isfinite(x0.hi) || x0.lo > x0.hi)
      return "x0 uniform range [a, b] needs finite a <= b";
  } else {
    if (x0.values.size() != static_cast<std::size_t>(records))
      return "x0 needs one value per record (" + std::to_string(records) + "), got " +
             std::to_string(x0.values.size());
    if (!all_finite(x0.values)) return "x0 values must be finite";
  }
  if (!x0.y_values.empty()) {
    if (x0.y_values.size() != static_cast<std::size_t>(records))
      return "y0 needs one value per record (" + std::to_string(records) + "), got " +
             std::to_string(x0.y_values.size());
    if (!all_finite(x0.y_values)) return "y0 values must be finite";
  } else if (x0.y_uniform) {
    if (!std::isfinite(x0.y_lo) || !std::isfinite(x0.y_hi) || x0.y_lo > x0.y_hi)
      return "y0 uniform range [a, b] needs finite a <= b";
  } else if (!std::isfinite(x0.y0)) {
    return "y0 must be finite";
  }
  if (!(sensor_noise >= 0.0) || !std::isfinite(sensor_noise))
    return "sensor_noise must be >= 0 (got " + num(sensor_noise) + ")";
  if (!(burn_in >= 0.0) || !std::isfinite(burn_in)) return "burn_in must be >= 0 (got " + num(burn_in) + ")";
  if (!(divergence_bound > 0.0)) return "divergence_bound must be > 0";
  // a record starting beyond the bound would count as diverged at its first step (and a state
  // near the largest double overflows every term of the model)
  const double x_most = x0.uniform ? std::max(std::abs(x0.lo), std::abs(x0.hi)) : largest_magnitude(x0.values);
  if (x_most > divergence_bound)
    return "x0 = " + num(x_most) + " lies beyond divergence_bound = " + num(divergence_bound) +
           ": a record starting there counts as diverged (start nearer 0 or raise divergence_bound)";
  const double y_most = !x0.y_values.empty() ? largest_magnitude(x0.y_values)
                        : x0.y_uniform       ? std::max(std::abs(x0.y_lo), std::abs(x0.y_hi))
                                             : std::abs(x0.y0);
  if (y_most > divergence_bound)
    return "y0 = " + num(y_most) + " lies beyond divergence_bound = " + num(divergence_bound) +
           ": a record starting there counts as diverged (start nearer 0 or raise divergence_bound)";
  if (!drive.empty() && !drive_per_record.empty()) return "give either drive or drive_per_record";
  if (!drive_per_record.empty() && drive_per_record.size() != static_cast<std::size_t>(records))
    return "drive_per_record needs one series per record";
  const double h = dt / substeps;
  if (!(h > 0.0) || !std::isfinite(h)) return "dt / substeps is not a usable step";
  return "";
}

std::string StatisticsOptions::invalid_reason() const {
  if (!(discard >= 0.0) || !std::isfinite(discard)) return "discard must be >= 0";
  if (batches < 1) return "batches must be >= 1";
  if (histograms) {
    if (!(x_min < x_max) || !std::isfinite(x_min) || !std::isfinite(x_max))
      return "histogram x range needs finite min < max";
    if (!(y_min < y_max) || !std::isfinite(y_min) || !std::isfinite(y_max))
      return "histogram y range needs finite min < max";
    if (nx < 1 || ny < 1) return "histograms need at least one cell per axis";
    if (nx * ny > 100000000) return "histogram grid too large (nx·ny > 1e8)";
  }
  return "";
}

void check_simulation(const Model& model, const SimulationOptions& o, const std::string& where) {
  if (auto why = o.invalid_reason(); !why.empty()) throw Error(where + ": " + why);
  validate_model(model, where + ": model");
  const CompiledModel cm = CompiledModel::from_model(model, where + ": model");

  // diffusion: a22 >= 0 for large |x| (the rule fpk-stationary applies too), and where records
  // start and beyond
  if (auto why = diffusion_negative_at_large_x(model); !why.empty()) throw Error(where + ": model " + why);
  double x_extent = 1.5;
  if (o.x0.uniform)
    x_extent = std::max({x_extent, std::abs(o.x0.lo), std::abs(o.x0.hi)});
  else
    for (double v : o.x0.values) x_extent = std::max(x_extent, std::abs(v));
  double y_extent = 1.0 + std::abs(o.x0.y0) + std::abs(o.x0.y_lo) + std::abs(o.x0.y_hi);
  for (double v : o.x0.y_values) y_extent = std::max(y_extent, std::abs(v));
  const int n = 200;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = 2.0 * x_extent * (2.0 * i / n - 1.0);
      const double y = 2.0 * y_extent * (2.0 * j / n - 1.0);
      const double a = cm.diffusion.eval(x, y);
      if (!std::isfinite(a))
        throw Error(where + ": model diffusion a22(" + num(x) + ", " + num(y) + ") = " + num(a) +
                    " overflows: initial states x0, y0 this far out are beyond what the model's terms can evaluate");
      if (!(a >= 0.0))
        throw Error(where + ": model diffusion a22(" + num(x) + ", " + num(y) + ") = " + num(a) +
                    " is negative (a22 is a variance rate and must be >= 0)");
    }

  // confinement: the restoring force (y-independent drift polynomial) for large |x|
  if (!o.allow_unconfined) {
    const XPolynomial f = cm.drift.by_ypow.empty() ? XPolynomial{} : cm.drift.by_ypow[0];
    auto c = f.coefficients();
    if (cm.impact) {
      if (c.size() < 2) c.resize(2, 0.0);
      c[1] -= cm.stop.stiffness();
    }
    const XPolynomial eff = XPolynomial::from_coefficients(c);
    const int d = eff.degree();
    const double lead = eff.leading_coefficient();
    if (d < 1 || d % 2 == 0 || lead >= 0.0) {
      std::string term = d < 0 ? "no restoring force" : d == 0 ? "a constant force" :
                         "leading restoring term " + num(lead) + "·x^" + std::to_string(d);
      throw Error(where + ": model potential does not confine (" + term +
                  "): records would escape to infinity. The highest power of x in the drift must "
                  "be odd with a negative coefficient (or add an impact_stop); set "
                  "allow_unconfined to simulate anyway");
    }
  }

  // drive
  const bool uses_u = cm.drift.drive != 0.0;
  const bool has_drive = !o.drive.empty() || !o.drive_per_record.empty();
  if (uses_u && !has_drive)
    throw Error(where + ": the model has a 'u' term but no drive was given");
  if (!uses_u && has_drive)
    throw Error(where + ": a drive was given but the model has no 'u' term");
  if (has_drive) {
    if (o.burn_in > 0.0)
      throw Error(where + ": burn_in cannot be used with a recorded drive (the drive has no "
                          "values before t = 0)");
    auto check_len = [&](const std::vector<double>& u, const std::string& what) {
      if (u.size() + 1 < o.samples)
        throw Error(where + ": " + what + " has " + std::to_string(u.size()) +
                    " values but the records need " + std::to_string(o.samples - 1) +
                    " (one per recorded interval)");
      if (!all_finite(u)) throw Error(where + ": " + what + " has non-finite values");
    };
    if (!o.drive.empty()) check_len(o.drive, "drive");
    for (std::size_t r = 0; r < o.drive_per_record.size(); ++r)
      check_len(o.drive_per_record[r], "drive of record " + std::to_string(r));
  }
}

void check_memory(const SimulationOptions& o, bool with_drive, double extra_values) {
  const double values = static_cast<double>(o.records) * static_cast<double>(o.samples) *
                            (1.0 + (o.record_y ? 1.0 : 0.0) + (with_drive ? 1.0 : 0.0)) +
                        std::max(extra_values, 0.0);
  const double limit = vehs::detail::default_memory_limit(o.memory_limit);
  if (values * 8.0 > limit)
    throw Error("simulation: the records would need " + num(values * 8.0 / 1e9) +
                " GB of memory (limit " + num(limit / 1e9) +
                " GB): simulate fewer or shorter records, or ask only for statistics");
}

namespace {

// Everything the engine needs, prepared up front.
void prepare(detail::RunContext& ctx, const CompiledModel& cm, const SimulationOptions& o) {
  ctx.model = &cm;
  ctx.options = &o;
  ctx.rng = CounterRng(o.seed);
  ctx.dt = o.dt;
  ctx.substeps = o.substeps;
  ctx.h = o.dt / o.substeps;
  ctx.samples = o.samples;
  ctx.burn_intervals = std::llround(o.burn_in / o.dt);
  const std::size_t R = static_cast<std::size_t>(o.records);
  ctx.x0.resize(R);
  ctx.y0.resize(R);
  ctx.eta0.assign(R, 0.0);
  for (std::size_t r = 0; r < R; ++r) {
    const std::uint64_t id = o.first_record + r;
    ctx.x0[r] = o.x0.uniform ? o.x0.lo + (o.x0.hi - o.x0.lo) * ctx.rng.uniform(id, Purpose::Initial, 0)
                             : o.x0.values[r];
    if (!o.x0.y_values.empty())
      ctx.y0[r] = o.x0.y_values[r];
    else if (o.x0.y_uniform)
      ctx.y0[r] = o.x0.y_lo + (o.x0.y_hi - o.x0.y_lo) * ctx.rng.uniform(id, Purpose::Initial, 1);
    else
      ctx.y0[r] = o.x0.y0;
    if (cm.colored) ctx.eta0[r] = cm.colored_stationary_sd() * ctx.rng.normal(id, Purpose::Initial, 4);
  }
  ctx.drive.clear();
  if (!o.drive.empty()) ctx.drive.assign(R, o.drive.data());
  for (const auto& u : o.drive_per_record) ctx.drive.push_back(u.data());
}

void run(detail::RunContext& ctx, Scheme scheme) {
  simd_level();  // reads VEHS_SIMD once; a bad value is an error of its own, not a failed record
  switch (scheme) {
    case Scheme::EulerMaruyama: detail::run_all<EulerMaruyamaStepper>(ctx); break;
    case Scheme::Rk4Euler: detail::run_all<Rk4EulerStepper>(ctx); break;
    case Scheme::Baoab: detail::run_all<BaoabStepper>(ctx); break;
    case Scheme::Taylor15: detail::run_all<Taylor15Stepper>(ctx); break;
  }
  if (ctx.error) std::rethrow_exception(ctx.error);  // not a divergence: the exception itself
  if (ctx.failed_record >= 0) {
    std::ostringstream os;
    os << "simulation: record " << ctx.failed_record << " " << ctx.failure << " at t = "
       << ctx.failed_time
       << " (diverged: reduce dt or increase substeps, and check that the potential confines and "
          "a22 stays >= 0)";
    throw Error(os.str());
  }
}

void allocate(Dataset& d, const SimulationOptions& o) {
  const bool with_drive = !o.drive.empty() || !o.drive_per_record.empty();
  check_memory(o, with_drive);
  // reuses the vectors' memory when `d` already has the right sizes (repeated simulations)
  d.records.clear();
  const std::size_t n = o.samples;
  d.x.resize(n * static_cast<std::size_t>(o.records));
  if (o.record_y)
    d.y.resize(d.x.size());
  else
    d.y.clear();
  if (with_drive)
    d.u.resize(d.x.size());
  else
    d.u.clear();
  for (int r = 0; r < o.records; ++r) {
    Record rec;
    rec.source = "simulation";
    rec.id = static_cast<long long>(o.first_record) + r;
    rec.first_line = 2 + static_cast<std::size_t>(r) * n;
    rec.t0 = 0.0;
    rec.dt = o.dt;
    rec.offset = static_cast<std::size_t>(r) * n;
    rec.size = n;
    d.records.push_back(rec);
    if (with_drive) {
      const auto& u = o.drive.empty() ? o.drive_per_record[static_cast<std::size_t>(r)] : o.drive;
      for (std::size_t i = 0; i < n; ++i) d.u[rec.offset + i] = i < u.size() ? u[i] : u.back();
    }
  }
}

void fill_summary(SimulationSummary* summary, const SimulationOptions& o, const detail::RunContext& ctx,
                  std::chrono::steady_clock::time_point start) {
  if (!summary) return;
  summary->records = static_cast<std::size_t>(o.records);
  summary->samples = static_cast<std::size_t>(o.records) * o.samples;
  summary->steps = static_cast<std::size_t>(o.records) *
                   ((o.samples - 1 + static_cast<std::size_t>(ctx.burn_intervals)) *
                    static_cast<std::size_t>(o.substeps));
  summary->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary->threads = max_threads();
  summary->steps_per_second = summary->seconds > 0 ? static_cast<double>(summary->steps) / summary->seconds : 0.0;
  summary->h = ctx.h;
  summary->scheme = enum_to_string(kSchemeNames, o.scheme);
}

MonteCarloStatistics finalize(const detail::RunContext& ctx, const StatisticsOptions& so,
                              std::size_t records, bool with_v) {
  MonteCarloStatistics st;
  st.records = records;
  st.samples_per_record = ctx.samples - ctx.stats_first;
  st.discard = static_cast<double>(ctx.stats_first) * ctx.dt;
  const std::size_t B = ctx.batches, n = st.samples_per_record;
  const bool spread = static_cast<int>(records) >= so.min_records_for_spread;
  st.error_method = spread ? "independent records" : "batch means";
  for (std::size_t b = 0; b < B; ++b) st.batch_lengths.push_back(static_cast<double>((b + 1) * n / B - b * n / B));
  for (int m = 0; m < detail::kMoments; ++m) {
    if (m == 6 && !with_v) continue;
    std::vector<Estimate> groups;
    std::vector<double> weights;
    std::vector<double> means(records), batch_means(records * B);
    for (std::size_t r = 0; r < records; ++r) {
      const double* sums = ctx.batch_sums.data() + (r * detail::kMoments + static_cast<std::size_t>(m)) * B;
      double record_total = 0.0;
      for (std::size_t b = 0; b < B; ++b) record_total += sums[b];
      means[r] = record_total / static_cast<double>(n);
      for (std::size_t b = 0; b < B; ++b) batch_means[r * B + b] = sums[b] / st.batch_lengths[b];
      if (spread) {
        groups.push_back({means[r], 0.0});
        weights.push_back(static_cast<double>(n));
      } else {
        for (std::size_t b = 0; b < B; ++b) {
          groups.push_back({batch_means[r * B + b], 0.0});
          weights.push_back(st.batch_lengths[b]);
        }
      }
    }
    st.moments.emplace_back(detail::kMomentNames[static_cast<std::size_t>(m)],
                            combine_independent(groups, weights));
    st.record_means.push_back(std::move(means));
    st.batch_means.push_back(std::move(batch_means));
  }
  if (ctx.histograms) {
    st.has_histograms = true;
    st.px = ctx.hx.front();
    st.py = ctx.hy.front();
    st.pxy = ctx.hxy.front();
    for (std::size_t t = 1; t < ctx.hx.size(); ++t) {
      st.px.merge(ctx.hx[t]);
      st.py.merge(ctx.hy[t]);
      st.pxy.merge(ctx.hxy[t]);
    }
  }
  return st;
}

void prepare_statistics(detail::RunContext& ctx, const StatisticsOptions& so, std::size_t records) {
  if (auto why = so.invalid_reason(); !why.empty()) throw Error("statistics: " + why);
  ctx.stats = true;
  ctx.stats_first = static_cast<std::size_t>(std::llround(so.discard / ctx.dt));
  if (ctx.stats_first >= ctx.samples)
    throw Error("statistics: discard (" + num(so.discard) + ") leaves no samples of the records (duration " +
                num(static_cast<double>(ctx.samples) * ctx.dt) + ")");
  ctx.batches = std::min(so.batches, ctx.samples - ctx.stats_first);
  ctx.batch_sums.assign(records * detail::kMoments * ctx.batches, 0.0);
  ctx.histograms = so.histograms;
  if (so.histograms) {
    const int threads = std::max(1, max_threads());
    ctx.hx.assign(static_cast<std::size_t>(threads), Histogram1D(so.x_min, so.x_max, so.nx));
    ctx.hy.assign(static_cast<std::size_t>(threads), Histogram1D(so.y_min, so.y_max, so.ny));
    ctx.hxy.assign(static_cast<std::size_t>(threads),
                   Histogram2D(so.x_min, so.x_max, so.nx, so.y_min, so.y_max, so.ny));
  }
}

}  // namespace

Dataset simulate(const Model& model, const SimulationOptions& o, SimulationSummary* summary) {
  Dataset d;
  simulate(model, o, d, summary);
  return d;
}

void simulate(const Model& model, const SimulationOptions& o, Dataset& d, SimulationSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  check_simulation(model, o);
  const CompiledModel cm = CompiledModel::from_model(model, "simulation: model");
  allocate(d, o);
  detail::RunContext ctx;
  prepare(ctx, cm, o);
  ctx.data = &d;
  vehs::detail::ProgressCounter progress(o.progress, "simulate",
                                        static_cast<long long>(o.records) * static_cast<long long>(o.samples));
  ctx.progress = &progress;
  run(ctx, o.scheme);
  progress.finish();
  fill_summary(summary, o, ctx, start);
}

MonteCarloStatistics simulate_statistics(const Model& model, const SimulationOptions& o,
                                         const StatisticsOptions& so, SimulationSummary* summary,
                                         Dataset* keep) {
  const auto start = std::chrono::steady_clock::now();
  check_simulation(model, o);
  const CompiledModel cm = CompiledModel::from_model(model, "simulation: model");
  detail::RunContext ctx;
  prepare(ctx, cm, o);
  prepare_statistics(ctx, so, static_cast<std::size_t>(o.records));
  if (keep) {
    allocate(*keep, o);
    ctx.data = keep;
  }
  vehs::detail::ProgressCounter progress(o.progress, "simulate",
                                        static_cast<long long>(o.records) * static_cast<long long>(o.samples));
  ctx.progress = &progress;
  run(ctx, o.scheme);
  progress.finish();
  fill_summary(summary, o, ctx, start);
  return finalize(ctx, so, static_cast<std::size_t>(o.records), cm.electro);
}

MonteCarloStatistics dataset_statistics(const Dataset& data, const StatisticsOptions& so) {
  require(data.has_y(), "statistics: the records have no y (true velocity) column");
  require(!data.records.empty(), "statistics: no records");
  const std::size_t n = data.records.front().size;
  for (const auto& r : data.records)
    require(r.size == n, "statistics: records differ in length (" + std::to_string(r.size) + " vs " +
                             std::to_string(n) + ")");
  detail::RunContext ctx;
  ctx.dt = data.records.front().dt;
  ctx.samples = n;
  prepare_statistics(ctx, so, data.records.size());
  const std::size_t first = ctx.stats_first, used = n - first, B = ctx.batches;
  for (std::size_t r = 0; r < data.records.size(); ++r) {
    const double* x = data.x_of(data.records[r]);
    const double* y = data.y_of(data.records[r]);
    for (std::size_t b = 0; b < B; ++b) {
      double s[detail::kMoments] = {};
      for (std::size_t i = first + b * used / B; i < first + (b + 1) * used / B; ++i) {
        const double x2 = x[i] * x[i];
        s[0] += x[i];
        s[1] += y[i];
        s[2] += x2;
        s[3] += y[i] * y[i];
        s[4] += x[i] * y[i];
        s[5] += x2 * x2;
        if (so.histograms) {
          ctx.hx[0].add(x[i]);
          ctx.hy[0].add(y[i]);
          ctx.hxy[0].add(x[i], y[i]);
        }
      }
      for (int m = 0; m < detail::kMoments; ++m)
        ctx.batch_sums[(r * detail::kMoments + static_cast<std::size_t>(m)) * B + b] = s[m];
    }
  }
  return finalize(ctx, so, data.records.size(), false);
}

const Estimate& MonteCarloStatistics::moment(const std::string& name) const {
  for (const auto& [k, e] : moments)
    if (k == name) return e;
  throw Error("statistics: no moment '" + name + "'");
}

}  // namespace vehs::sim
