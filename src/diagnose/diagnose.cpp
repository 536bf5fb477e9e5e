#include "vehs/diagnose/diagnose.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>

#include "twins.hpp"
#include "unit_stats.hpp"
#include "vehs/diagnose/distributions.hpp"
#include "vehs/conventions.hpp"
#include "vehs/core/error.hpp"
#include "vehs/core/detail/progress_counter.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/fpk/stationary.hpp"
#include "vehs/identify/identify.hpp"

namespace vehs::diagnose {

using detail::StatsSetup;
using detail::UnitSpan;
using detail::UnitStats;

std::string Options::invalid_reason() const {
  if (stride < 0) return "stride must be >= 0";
  if (lens == LensChoice::Forward && stride > 1) return "stride applies to central kinematics only";
  if (replicates < 0 || replicates > 1000) return "replicates must be in [0, 1000]";
  if (twin_substeps < 0) return "twin_substeps must be >= 0";
  if (map_bins_x < 2 || map_bins_v < 2 || map_bins_x > 200 || map_bins_v > 200)
    return "map bins must be in [2, 200] per axis";
  if (!(min_bin_count >= 10)) return "min_bin_count must be >= 10";
  if (min_units < 4) return "min_units must be >= 4";
  if (residual_lags < 1) return "residual_lags must be >= 1";
  if (!(alpha > 0.0 && alpha < 0.5)) return "alpha must be in (0, 0.5)";
  if (fpk_cells < 20 || fpk_cells > 2000) return "fpk_cells must be in [20, 2000]";
  if (!(expected_dt >= 0.0)) return "dt must be > 0";
  if (!(suspect_samples >= 0.0)) return "suspect_samples must be >= 0";
  if (parameter_draws < 2 || parameter_draws > 200) return "parameter_draws must be in [2, 200]";
  if (!(parameter_fit_samples >= 1e4)) return "parameter_fit_samples must be >= 10000";
  return suspects.invalid_reason();
}

namespace {

std::string fmt(double v, int digits = 4) {
  std::ostringstream os;
  os.precision(digits);
  os << v;
  return os.str();
}

double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

std::size_t pow2_at_most(std::size_t n) {
  std::size_t p = 1;
  while (p * 2 <= n) p *= 2;
  return p;
}

/// Value and cluster (delta-method jackknife) standard error of ΣN/ΣD over units.
struct Ratio {
  double value = 0.0, se = 0.0;
};
Ratio ratio_over_units(const std::vector<double>& N, const std::vector<double>& D) {
  const double sn = std::accumulate(N.begin(), N.end(), 0.0), sd = std::accumulate(D.begin(), D.end(), 0.0);
  Ratio r;
  if (!(sd > 0.0)) return r;
  r.value = sn / sd;
  const double U = static_cast<double>(N.size());
  if (U < 2) return r;
  double ss = 0.0;
  for (std::size_t j = 0; j < N.size(); ++j) ss += (N[j] - r.value * D[j]) * (N[j] - r.value * D[j]);
  r.se = std::sqrt(U / (U - 1.0) * ss) / sd;
  return r;
}

/// Mean and standard error over units of per-unit values (skipping NaN).
Ratio mean_over_units(const std::vector<double>& v) {
  Ratio r;
  double s = 0.0, n = 0.0;
  for (double x : v)
    if (std::isfinite(x)) s += x, n += 1.0;
  if (n == 0) return r;
  r.value = s / n;
  if (n < 2) return r;
  double ss = 0.0;
  for (double x : v)
    if (std::isfinite(x)) ss += (x - r.value) * (x - r.value);
  r.se = std::sqrt(ss / (n - 1.0) / n);
  return r;
}

/// Log-spaced bands of frequency indices [1, kmax]: edges e_0 = 1 < … < e_nb = kmax + 1.
std::vector<std::size_t> log_bands(std::size_t kmax, int nb) {
  std::vector<std::size_t> e{1};
  for (int b = 1; b <= nb; ++b) {
    const auto k = static_cast<std::size_t>(
        std::llround(std::exp(std::log(static_cast<double>(kmax + 1)) * b / nb)));
    if (k > e.back()) e.push_back(std::min(k, kmax + 1));
  }
  if (e.back() != kmax + 1) e.push_back(kmax + 1);
  return e;
}

double band_mean(const std::vector<double>& psd, std::size_t a, std::size_t b) {
  double s = 0.0;
  for (std::size_t k = a; k < b; ++k) s += psd[k];
  return s / static_cast<double>(b - a);
}

/// identify's sampling diagnosis on the first samples of every record.
struct Pilot {
  bool ok = false;
  SamplingVerdict verdict = SamplingVerdict::Unknown;
  Estimator estimator = Estimator::Auto;
  std::string error;
  int stride = 1;
  double sensor_noise_sd = 0.0;
};
Pilot sampling_pilot(const Model& model, const Dataset& data) {
  Pilot p;
  const std::size_t cap = std::max<std::size_t>(4000, 600000 / data.records.size());
  const Dataset sub = leading_samples(data, [&](std::size_t, const Record&, std::size_t) { return cap; });
  identify::Options o;
  o.drift_library = terms_of(model.drift);
  o.diffusion_library = terms_of(model.diffusion);
  o.sparsity = identify::Sparsity::None;
  o.folds = 1;
  o.estimator = Estimator::Auto;
  try {
    const FitInfo fit = *identify::identify(sub, o).model.fit;
    p.ok = true;
    p.verdict = fit.sampling.verdict;
    p.estimator = fit.estimator;
    p.stride = fit.stride;
    p.sensor_noise_sd = fit.sampling.sensor_noise_sd;
  } catch (const std::exception& e) {
    p.error = e.what();
  }
  return p;
}

/// The sampling diagnosis for a model WITH dynamic effects, from the model's own one-step
/// residuals. identify's pilot fits only the model's terms, so the forces of stops, forcing or a
/// hidden state stay in its residuals and their memory reads as sensor noise. Here the residuals
/// e = â − b2 (ULI kinematics at stride 1, b2 including the explicit forces) are used, with
/// identify's sampling_rule (lag 3 as the reference for what a slowly varying force leaves).
Pilot model_sampling_pilot(const Model& model, const Dataset& data) {
  Pilot p;
  Lens L;
  L.kinematics = Kinematics::Central;
  L.stride = 1;
  L.dt = data.common_dt();
  const ModelLens ml(model, L);
  const std::size_t cap = std::max<std::size_t>(4000, 600000 / std::max<std::size_t>(1, data.records.size()));
  double c[4] = {0, 0, 0, 0};
  std::vector<double> e;
  for (const auto& r : data.records) {
    const std::size_t n = std::min(r.size, cap);
    if (n < 16) continue;
    const double* x = data.x_of(r);
    const double* u = data.has_u() ? data.u_of(r) : nullptr;
    e.clear();
    for (std::size_t i = L.lead(); i + L.trail() < n; ++i) {
      double xi, v, a;
      L.at(x, i, xi, v, a);
      e.push_back(a - ml.b2(xi, v, u ? u[i] : 0.0, r.t0 + static_cast<double>(i) * L.dt));
    }
    for (int l = 0; l < 4; ++l)
      for (std::size_t i = 0; i + static_cast<std::size_t>(l) < e.size(); ++i) c[l] += e[i] * e[i + static_cast<std::size_t>(l)];
  }
  if (!(c[0] > 0.0) || !std::isfinite(c[0])) {
    p.error = "no usable rows for the sampling diagnosis";
    return p;
  }
  double rows = 0.0;
  for (const auto& r : data.records) rows += static_cast<double>(L.rows(std::min(r.size, cap)));
  const identify::SamplingRule rule = identify::sampling_rule(c[1] / c[0], c[2] / c[0], c[3] / c[0], rows);
  p.ok = true;
  p.verdict = rule.verdict;
  p.estimator = rule.noisy ? Estimator::Noisy : rule.continuous ? Estimator::Uli : Estimator::Forward;
  p.stride = 1;
  const double h = L.h();
  p.sensor_noise_sd = rule.noisy ? std::sqrt(rule.noise_share * (c[0] / rows) * h * h * h * h / 6.0) : 0.0;
  return p;
}

/// The confirmation of close contenders (see suspects.hpp): colored_noise against the
/// deterministic dynamic forces, by refits and their diagnoses.
void confirm_contenders(const Model& model, const Dataset& data, const Lens& lens, const Options& opt,
                        SuspectReport& rep) {
  auto& ranked = rep.ranked;
  auto method = [](const std::string& effect) {
    return suspect_method(enum_from_string(kEffectNames, effect, "suspect"));
  };
  auto contender = [&](const std::string& effect) {
    const SuspectMethod m = method(effect);
    return m == SuspectMethod::DynamicForce || m == SuspectMethod::ColoredExcitation;
  };
  if (ranked.empty() || !ranked[0].held_out_significant || !contender(ranked[0].effect)) return;
  // paired z of the leader's gain over suspect i's, block by block (infinite: not comparable)
  auto paired_z = [&](std::size_t i) {
    const auto& a = ranked[0].block_gain;
    const auto& b = ranked[i].block_gain;
    if (i == 0) return 0.0;
    if (a.size() != b.size() || a.size() < 2) return std::numeric_limits<double>::infinity();
    std::vector<double> diff(a.size());
    for (std::size_t k = 0; k < a.size(); ++k) diff[k] = a[k] - b[k];
    return block_z(diff);
  };
  std::vector<std::size_t> order;  // forces by evidence, colored_noise last
  long colored = -1;
  for (std::size_t i = 0; i < ranked.size(); ++i)
    if (std::isfinite(ranked[i].evidence) && ranked[i].evidence > 0.0 && contender(ranked[i].effect) &&
        paired_z(i) < 2.0) {
      if (method(ranked[i].effect) == SuspectMethod::ColoredExcitation) colored = static_cast<long>(i);
      else order.push_back(i);
    }
  if (colored < 0 || order.empty()) return;
  order.push_back(static_cast<std::size_t>(colored));
  Options sub = opt;
  sub.suspects.enabled = false;
  sub.progress = nullptr;
  std::string tried;
  for (const std::size_t i : order) {
    Suspect& sp = ranked[i];
    identify::Options io = refit_options(model, lens);
    Effect e;
    e.id = enum_from_string(kEffectNames, sp.effect, "suspect");
    io.effects.push_back(e);
    try {
      const Result r = diagnose(identify::identify(data, io).model, data, sub);
      sp.refit_verdict = r.verdict;
      sp.refit_score = r.score;
    } catch (const std::exception& ex) {
      sp.refit_verdict = std::string("refit failed: ") + ex.what();
    }
    tried += (tried.empty() ? "" : ", ") + sp.effect + " " +
             (std::isfinite(sp.refit_score) ? sp.refit_verdict + " (score " + fmt(sp.refit_score) + ")" : sp.refit_verdict);
    if (sp.refit_verdict == "adequate") {
      if (i != 0) {
        Suspect moved = sp;
        ranked.erase(ranked.begin() + static_cast<long>(i));
        ranked.insert(ranked.begin(), std::move(moved));
      }
      break;
    }
  }
  rep.note += (rep.note.empty() ? "" : " ") +
              std::string("colored_noise and a deterministic dynamic force explain the held-out rows about equally well; "
                          "refits with them "
                          "(forces first, colored_noise last; the first adequate one is ranked first): ") +
              tried + ".";
}

}  // namespace

Result diagnose(const Model& model, const Dataset& data, const Options& opt) {
  const auto t_start = std::chrono::steady_clock::now();
  auto lap = [&, t = t_start](Result& res, const char* what) mutable {
    const auto now = std::chrono::steady_clock::now();
    res.timings.emplace_back(what, std::chrono::duration<double>(now - t).count());
    t = now;
  };
  if (auto why = opt.invalid_reason(); !why.empty()) throw Error("diagnose: " + why);
  validate_model(model, "model");
  require(!model.diffusion.empty(),
          "the model has no diffusion terms: its one-step residuals cannot be whitened and its "
          "twins cannot be simulated (the model file needs a 'diffusion' object)");
  require(!model.drift.empty(), "the model has no drift terms (the model file needs a 'drift' object)");
  require(!data.records.empty(), "no records to diagnose");
  if (model.uses_drive())
    require(data.has_u(),
            "the model has a drive term 'u' but the data have no drive column (name it with "
            "'columns': {\"u\": ...})");
  RecordChecks checks;
  checks.expected_dt = opt.expected_dt;
  check_records(data, checks);
  const double dt = data.common_dt();

  Result res;
  res.records = data.records.size();
  res.samples = data.total_samples();
  SamplingInfo& si = res.sampling;
  si.data_dt = dt;
  // ---- what the model says about the data it was fitted to
  const FitInfo fit = model.fit.value_or(FitInfo{});
  si.model_dt = fit.sampling.dt;
  si.model_verdict = fit.sampling.verdict;
  si.model_estimator = fit.estimator;
  const int model_stride = fit.stride;
  const double model_noise = fit.sampling.sensor_noise_sd;
  if (opt.check_model_sampling && si.model_dt > 0.0 && std::abs(si.model_dt - dt) > 1e-6 * dt)
    throw Error("the model was identified from data sampled at dt = " + fmt(si.model_dt, 8) +
                " (its 'sampling.dt') but these data are sampled at dt = " + fmt(dt, 8) +
                ": coefficients fitted to a discrete scheme depend on the interval; diagnose data "
                "sampled like the model's, or set check_model_sampling to false");

  // ---- the data's own sampling diagnosis (identify's pilot, model terms as the library)
  const Pilot pilot = model.has_dynamic_effects() ? model_sampling_pilot(model, data) : sampling_pilot(model, data);
  si.data_verdict = pilot.ok ? pilot.verdict : SamplingVerdict::Unknown;
  const SamplingVerdict assumed =
      si.model_verdict == SamplingVerdict::Unknown ? SamplingVerdict::ContinuousTime : si.model_verdict;
  if (!pilot.ok)
    res.warnings.push_back("the sampling diagnosis of the data failed (" + pilot.error + "); assuming " +
                           enum_to_string(kSamplingVerdictNames, assumed) + " data");
  if (pilot.ok && si.model_verdict != SamplingVerdict::Unknown && si.model_verdict != pilot.verdict)
    res.warnings.push_back("the model file says its data were '" + enum_to_string(kSamplingVerdictNames, si.model_verdict) +
                           "' but these data look '" + enum_to_string(kSamplingVerdictNames, pilot.verdict) + "'");
  const SamplingVerdict verdict = pilot.ok ? pilot.verdict : assumed;
  lap(res, "sampling_pilot");

  // ---- the lens
  Lens lens;
  lens.dt = dt;
  {
    bool forward = false;
    int stride = 1;
    if (opt.lens == LensChoice::Forward) {
      forward = true;
    } else if (opt.lens == LensChoice::Central) {
      stride = model_stride >= 1 ? model_stride : (pilot.ok ? pilot.stride : 1);
    } else if (si.model_estimator != Estimator::Auto) {
      forward = !uses_central_kinematics(si.model_estimator);
      stride = model_stride >= 1 ? model_stride : 1;
    } else if (pilot.ok) {
      forward = !uses_central_kinematics(pilot.estimator);
      stride = pilot.stride;
    }
    if (opt.stride > 0) stride = opt.stride;
    lens.kinematics = forward ? Kinematics::Forward : Kinematics::Central;
    lens.stride = forward ? 1 : std::max(stride, 1);
    if (opt.sensor_noise >= 0.0)
      lens.sensor_noise_sd = opt.sensor_noise;
    else if (model_noise > 0.0)
      lens.sensor_noise_sd = model_noise;
    else if (pilot.ok && pilot.verdict == SamplingVerdict::Noisy)
      lens.sensor_noise_sd = pilot.sensor_noise_sd;
  }
  if (auto why = lens.invalid_reason(); !why.empty()) throw Error("diagnose: lens: " + why);
  res.lens = lens;
  si.sensor_noise_sd = lens.sensor_noise_sd;
  const ModelLens mlens(model, lens);

  // ---- units
  const std::size_t nrec = data.records.size();
  const std::size_t per = nrec >= static_cast<std::size_t>(opt.min_units)
                              ? 1
                              : (static_cast<std::size_t>(opt.min_units) + nrec - 1) / nrec;
  std::vector<UnitSpan> units;
  std::size_t rows_total = 0, min_unit_len = std::numeric_limits<std::size_t>::max(), min_unit_rows = min_unit_len;
  for (std::size_t r = 0; r < nrec; ++r) {
    const std::size_t n = data.records[r].size;
    const std::size_t nrows = lens.rows(n);
    rows_total += nrows;
    std::size_t blocks = per;
    while (blocks > 1 && n / blocks < 256) --blocks;
    for (std::size_t b = 0; b < blocks; ++b) {
      UnitSpan u{r, n * b / blocks, n * (b + 1) / blocks};
      units.push_back(u);
      min_unit_len = std::min(min_unit_len, u.end - u.begin);
      const std::size_t ub = std::max(u.begin, lens.lead()), ue = std::min(u.end, n - std::min(n, lens.trail()));
      min_unit_rows = std::min(min_unit_rows, ue > ub ? ue - ub : 0);
    }
  }
  res.rows = rows_total;
  res.units = units.size();
  res.unit_kind = per == 1 ? "records" : "time blocks (" + std::to_string(per) + " per record)";
  if (rows_total < 2000)
    throw Error("too little data: " + std::to_string(rows_total) + " usable rows in " + std::to_string(nrec) +
                " records (at least 2000 needed for the one-step statistics)");
  if (min_unit_rows < 32)
    throw Error("a record is too short: a unit of only " + std::to_string(min_unit_rows) +
                " usable rows (records need at least 32 rows beyond the lens's stencil)");
  const int U = static_cast<int>(units.size());
  if (U < 8)
    res.warnings.push_back("only " + std::to_string(U) + " units: the tests have little power and their calibration rests on few degrees of freedom");
  if (per > 1)
    res.warnings.push_back("fewer records than min_units: records are cut into time blocks treated as "
                           "independent units, which assumes blocks longer than the correlation time");

  // ---- setup from a subsample of the data's rows
  StatsSetup setup;
  setup.lens = &mlens;
  setup.dt = dt;
  setup.nx = opt.map_bins_x;
  setup.nv = opt.map_bins_v;
  std::vector<double> xs, vs;
  {
    const std::size_t step = std::max<std::size_t>(1, rows_total / 200000);
    for (const auto& r : data.records) {
      const double* x = data.x_of(r);
      const double* u = data.u_of(r);
      const std::size_t i1 = r.size > lens.trail() ? r.size - lens.trail() : 0;
      for (std::size_t i = lens.lead(); i < i1; i += step) {
        double xi, v, a;
        lens.at(x, i, xi, v, a);
        xs.push_back(xi);
        vs.push_back(v);
        if (!(mlens.residual_variance(xi, v) > 0.0))
          throw Error("the model's diffusion a22 is not positive at x = " + fmt(xi) + ", v = " + fmt(v) +
                      " (" + record_name(r) + ", sample " + std::to_string(i) +
                      "): it cannot describe data there");
        (void)u;
      }
    }
  }
  {
    std::vector<double> a = xs, b = vs;
    setup.x_lo = quantile(a, 0.002), setup.x_hi = quantile(a, 0.998);
    setup.v_lo = quantile(b, 0.002), setup.v_hi = quantile(b, 0.998);
    if (!(setup.x_hi > setup.x_lo)) setup.x_hi = setup.x_lo + 1e-9;
    if (!(setup.v_hi > setup.v_lo)) setup.v_hi = setup.v_lo + 1e-9;
    setup.shape_xc = 0.5 * (setup.x_lo + setup.x_hi);
    setup.shape_xs = 0.25 * (setup.x_hi - setup.x_lo);
    setup.shape_vs = 0.25 * (setup.v_hi - setup.v_lo);
    const double xa = quantile(a, 0.0005), xb = quantile(a, 0.9995);
    const double va = quantile(b, 0.0005), vb = quantile(b, 0.9995);
    const double wx = std::max(xb - xa, 1e-9), wv = std::max(vb - va, 1e-9);
    setup.hx_lo = setup.hxy_x_lo = xa - 0.05 * wx;
    setup.hx_hi = setup.hxy_x_hi = xb + 0.05 * wx;
    setup.hxy_v_lo = va - 0.05 * wv;
    setup.hxy_v_hi = vb + 0.05 * wv;
    // coarse cells of the pdf test: at most U/4 dimensions
    const int pmax = std::max(1, U / 4);
    int ncv = 3, ncx = std::min(6, (pmax + 1) / 3);
    if (ncx < 2) {
      ncv = 1;
      ncx = std::min(6, pmax + 1);
    }
    for (int i = 1; i < ncx; ++i) setup.cell_x.push_back(quantile(a, static_cast<double>(i) / ncx));
    for (int j = 1; j < ncv; ++j) setup.cell_v.push_back(quantile(b, static_cast<double>(j) / ncv));
  }
  // wells from the model's potential over the data's range
  fpk::FpkModel* fm_ptr = nullptr;
  std::unique_ptr<fpk::FpkModel> fm;
  try {
    fm = std::make_unique<fpk::FpkModel>(model, "model");
    fm_ptr = fm.get();
  } catch (const Error& e) {
    res.fpk_note = std::string("no stationary FPK for this model: ") + e.what();
  }
  if (fm_ptr) {
    const double xmin = *std::min_element(xs.begin(), xs.end()), xmax = *std::max_element(xs.begin(), xs.end());
    const double w = xmax - xmin;
    auto wells = fpk::find_wells(*fm_ptr, xmin - 0.1 * w, xmax + 0.1 * w);
    if (wells.size() >= 2 && static_cast<int>(wells.size()) <= std::max(2, U / 4)) {
      for (std::size_t k = 0; k < wells.size(); ++k) {
        const fpk::Well& wl = wells[k];
        WellInfo wi;
        wi.x_min = wl.x_min;
        wi.lo = k == 0 ? -std::numeric_limits<double>::infinity() : wl.lo;
        wi.hi = k + 1 == wells.size() ? std::numeric_limits<double>::infinity() : wl.hi;
        // core: where U is below the midpoint between the minimum and the lower interior barrier
        double barrier = std::numeric_limits<double>::infinity();
        if (k > 0) barrier = std::min(barrier, fm_ptr->potential(wl.lo));
        if (k + 1 < wells.size()) barrier = std::min(barrier, fm_ptr->potential(wl.hi));
        const double level = wl.potential + 0.5 * (barrier - wl.potential);
        const double step = (wl.hi - wl.lo) / 2000.0;
        double a = wl.x_min, b = wl.x_min;
        while (a - step > wl.lo && fm_ptr->potential(a - step) < level) a -= step;
        while (b + step < wl.hi && fm_ptr->potential(b + step) < level) b += step;
        wi.core_lo = a;
        wi.core_hi = b;
        res.wells.push_back(wi);
        if (k > 0) setup.well_bounds.push_back(wl.lo);
        setup.core_lo.push_back(a);
        setup.core_hi.push_back(b);
      }
    } else if (wells.size() > 2) {
      res.warnings.push_back("the model has " + std::to_string(wells.size()) + " wells but only " + std::to_string(U) +
                             " units: the well test is skipped");
    }
  }
  // spectra, ACFs
  // x is block-averaged so that a spectrum segment of at most 2048 block means spans about a
  // quarter of the shortest unit; the residual spectrum runs at the row rate
  setup.x_decimation = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(static_cast<double>(min_unit_len) / 4.0 / 2048.0)));
  const std::size_t n_dec = min_unit_len / setup.x_decimation;
  setup.seg_x = std::clamp<std::size_t>(pow2_at_most(n_dec / 4), 16, 2048);
  setup.lags_x = std::max<std::size_t>(1, std::min(setup.seg_x / 2, n_dec / 2));
  setup.seg_r = std::clamp<std::size_t>(pow2_at_most(min_unit_rows / 8), 16, 8192);
  setup.lags_r = std::max<std::size_t>(1, std::min(static_cast<std::size_t>(opt.residual_lags), min_unit_rows / 4));
  lap(res, "setup");

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
        detail::compute_unit(setup, d.x_of(rec), model.uses_drive() ? data.u_of(data.records[s.record]) : nullptr,
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
  const int R = opt.replicates > 0
                    ? opt.replicates
                    : std::clamp(static_cast<int>(std::ceil(2e6 / static_cast<double>(std::max<std::size_t>(res.samples, 1)))), 1, 8);
  si.replicates = R;
  vehs::detail::ProgressCounter prog(opt.progress, "diagnose", static_cast<long long>(units.size()) * (R + 1));
  std::vector<UnitStats> dstats, tstats, rep0;
  run_units(data, dstats, false, prog);
  lap(res, "data_statistics");

  detail::TwinSettings ts;
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
  detail::TwinSimulator twins(model, data, ts);
  tstats.resize(units.size());
  for (auto& t : tstats) t.init(setup);
  std::vector<std::vector<double>> rep_hx, rep_hxy;  // pooled per replicate (Hellinger null)
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
  lap(res, "twin_statistics");

  double invalid = 0.0;
  for (const auto& s : dstats) invalid += s.invalid_rows;
  if (invalid > 0)
    res.warnings.push_back(fmt(invalid, 6) + " data rows where the model's residual variance is not positive were left out");

  // ================================================================== tests
  const auto Ud = static_cast<std::size_t>(U);
  // ---- one-step map: paired jackknife over units, per bin
  {
    OneStepMap& mp = res.map;
    mp.nx = setup.nx;
    mp.nv = setup.nv;
    mp.x_lo = setup.x_lo;
    mp.x_hi = setup.x_hi;
    mp.v_lo = setup.v_lo;
    mp.v_hi = setup.v_hi;
    const int B = setup.map_bins();
    mp.bins.resize(static_cast<std::size_t>(B));
    std::vector<double> tvals, nus;
    struct Mom {
      double n, m, var, kurt;
    };
    auto moments = [](const double* s) {
      Mom o{s[0], 0, 0, 0};
      if (s[0] <= 0) return o;
      const double m = s[1] / s[0], e2 = s[2] / s[0], e3 = s[3] / s[0], e4 = s[4] / s[0];
      o.m = m;
      o.var = e2 - m * m;
      const double m4 = e4 - 4 * m * e3 + 6 * m * m * e2 - 3 * m * m * m * m;
      o.kurt = o.var > 0 ? m4 / (o.var * o.var) : 0.0;
      return o;
    };
    for (int b = 0; b < B; ++b) {
      double D[5] = {0, 0, 0, 0, 0}, T[5] = {0, 0, 0, 0, 0};
      int ud = 0, ut = 0;
      for (std::size_t j = 0; j < Ud; ++j) {
        const double* d = dstats[j].map.data() + b * 5;
        const double* t = tstats[j].map.data() + b * 5;
        for (int k = 0; k < 5; ++k) D[k] += d[k], T[k] += t[k];
        ud += d[0] > 0;
        ut += t[0] > 0;
      }
      MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
      const int i = b / setup.nv, jv = b % setup.nv;
      mb.x = setup.x_lo + (i + 0.5) * (setup.x_hi - setup.x_lo) / setup.nx;
      mb.v = setup.v_lo + (jv + 0.5) * (setup.v_hi - setup.v_lo) / setup.nv;
      const Mom md = moments(D), mt = moments(T);
      mb.n_data = md.n;
      mb.n_twin = mt.n / R;
      mb.mean_data = md.m;
      mb.mean_twin = mt.m;
      mb.var_data = md.var;
      mb.var_twin = mt.var;
      mb.kurt_data = md.kurt;
      mb.kurt_twin = mt.kurt;
      if (md.n < opt.min_bin_count || mt.n / R < opt.min_bin_count || ud < 2 || ut < 2 || U < 3) continue;
      const double th[3] = {md.m - mt.m, std::log(md.var / mt.var), md.kurt - mt.kurt};
      double acc[3] = {0, 0, 0}, acc2[3] = {0, 0, 0};
      std::vector<double> jk(3 * Ud);
      for (std::size_t j = 0; j < Ud; ++j) {
        double Dj[5], Tj[5];
        const double* d = dstats[j].map.data() + b * 5;
        const double* t = tstats[j].map.data() + b * 5;
        for (int k = 0; k < 5; ++k) Dj[k] = D[k] - d[k], Tj[k] = T[k] - t[k];
        const Mom a = moments(Dj), c = moments(Tj);
        const double v[3] = {a.m - c.m, (a.var > 0 && c.var > 0) ? std::log(a.var / c.var) : th[1], a.kurt - c.kurt};
        for (int k = 0; k < 3; ++k) {
          jk[3 * j + static_cast<std::size_t>(k)] = v[k];
          acc[k] += v[k];
        }
      }
      for (int k = 0; k < 3; ++k) {
        const double mean = acc[k] / static_cast<double>(Ud);
        for (std::size_t j = 0; j < Ud; ++j) {
          const double e = jk[3 * j + static_cast<std::size_t>(k)] - mean;
          acc2[k] += e * e;
        }
      }
      double z[3];
      for (int k = 0; k < 3; ++k) {
        const double se = std::sqrt((static_cast<double>(Ud) - 1.0) / static_cast<double>(Ud) * acc2[k]);
        z[k] = se > 0 ? th[k] / se : 0.0;
      }
      mb.z_mean = z[0];
      mb.z_var = z[1];
      mb.z_kurt = z[2];
      mb.used = true;
      tvals.push_back(z[0]);
      tvals.push_back(z[1]);
      nus.push_back(U - 1.0);
      nus.push_back(U - 1.0);
    }
    Component c{"one_step",
                "whitened one-step residual mean and log-variance per (x, v) bin, data vs twins",
                combine_t(tvals, nus)};
    if (!c.test.available) c.test.note = "no bin has " + fmt(opt.min_bin_count) + " rows on both sides";
    res.components.push_back(c);
    std::vector<int> idx;
    for (int b = 0; b < B; ++b)
      if (mp.bins[static_cast<std::size_t>(b)].used) idx.push_back(b);
    std::sort(idx.begin(), idx.end(), [&](int a, int b) {
      return std::abs(mp.bins[static_cast<std::size_t>(a)].z_mean) > std::abs(mp.bins[static_cast<std::size_t>(b)].z_mean);
    });
    if (idx.size() > 10) idx.resize(10);
    mp.worst = idx;
    auto profile = [&](bool over_v, bool mean_z) {
      const int n = over_v ? setup.nv : setup.nx;
      std::vector<double> s2(static_cast<std::size_t>(n), 0.0), cnt(static_cast<std::size_t>(n), 0.0);
      for (int b = 0; b < B; ++b) {
        const MapBin& mb = mp.bins[static_cast<std::size_t>(b)];
        if (!mb.used) continue;
        const auto k = static_cast<std::size_t>(over_v ? b % setup.nv : b / setup.nv);
        const double z = mean_z ? mb.z_mean : mb.z_var;
        s2[k] += z * z;
        cnt[k] += 1.0;
      }
      for (std::size_t k = 0; k < s2.size(); ++k)
        s2[k] = cnt[k] > 0 ? s2[k] / cnt[k] : std::numeric_limits<double>::quiet_NaN();
      return s2;
    };
    mp.v_profile_mean = profile(true, true);
    mp.v_profile_var = profile(true, false);
    mp.x_profile_mean = profile(false, true);
    mp.x_profile_var = profile(false, false);
  }

  // ---- paired components: per-unit difference vectors f(a, b) (false when undefined)
  using DiffFn = std::function<bool(const UnitStats&, const UnitStats&, Eigen::VectorXd&)>;
  auto unit_diffs = [&](const DiffFn& f, const std::vector<UnitStats>& A, const std::vector<UnitStats>& B, int p) {
    std::vector<Eigen::VectorXd> rows;
    Eigen::VectorXd d(p);
    for (std::size_t j = 0; j < A.size(); ++j)
      if (f(A[j], B[j], d)) rows.push_back(d);
    Eigen::MatrixXd M(static_cast<Eigen::Index>(rows.size()), p);
    for (std::size_t i = 0; i < rows.size(); ++i) M.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
    return M;
  };
  auto rows_of = [](const UnitStats& s) { return std::accumulate(s.cells.begin(), s.cells.end(), 0.0); };
  const int pmax = std::max(1, U / 4);
  const auto edges_r = log_bands(setup.seg_r / 2, std::min(12, pmax));
  const auto edges_x = log_bands(setup.seg_x / 2, std::min(12, pmax));
  auto spectrum_fn = [&](const std::vector<std::size_t>& edges, bool residual) -> DiffFn {
    return [&edges, residual](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
      const auto& pa = residual ? a.rpsd : a.xpsd;
      const auto& pb = residual ? b.rpsd : b.xpsd;
      if (!(a.replicates > 0 && b.replicates > 0)) return false;
      for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
        const double va = band_mean(pa, edges[k], edges[k + 1]) / a.replicates;
        const double vb = band_mean(pb, edges[k], edges[k + 1]) / b.replicates;
        if (!(va > 0 && vb > 0)) return false;
        d[static_cast<Eigen::Index>(k)] = std::log(va / vb);
      }
      return true;
    };
  };
  const int C = setup.cells();
  const int W = setup.wells() >= 2 ? setup.wells() : 0;
  struct Paired {
    std::string name, what;
    DiffFn f;
    int p;
    /// the model's parameter uncertainty moves it (stationary statistics, x spectrum, and the
    /// residual shapes: data residuals are whitened by fitted coefficients whose error and
    /// estimator bias the twins do not share)
    bool parameter_sensitive;
  };
  std::vector<Paired> paired;
  auto shape_fn = [&](bool noise) -> DiffFn {
    return [noise](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
      if (!(a.rows > 0 && b.rows > 0)) return false;
      const auto& sa = noise ? a.noise_shape : a.drift_shape;
      const auto& sb = noise ? b.noise_shape : b.drift_shape;
      for (std::size_t k = 0; k < sa.size(); ++k) d[static_cast<Eigen::Index>(k)] = sa[k] / a.rows - sb[k] / b.rows;
      return true;
    };
  };
  paired.push_back({"drift_shape",
                    "mean of the whitened residual times low-order functions of (x, v) (polynomials to third order, "
                    "sign(v), v|v|): smooth misfits of the drift such as missing damping or stiffness terms",
                    shape_fn(false), detail::kDriftShape, true});
  paired.push_back({"noise_shape",
                    "mean of the squared whitened residual times polynomials of (x, v) to second order: a22 with the "
                    "wrong dependence on x or v (e.g. velocity-dependent noise)",
                    shape_fn(true), detail::kNoiseShape, true});
  paired.push_back({"residual_spectrum",
                    "log spectrum of the whitened residuals in log-spaced frequency bands (memory, periodic forcing)",
                    spectrum_fn(edges_r, true), static_cast<int>(edges_r.size()) - 1, false});
  if (C >= 2)
    paired.push_back({"pdf", "occupation of " + std::to_string(C) + " coarse (x, v) cells (quantiles of the data)",
                      [&, C](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
                        const double na = rows_of(a), nb = rows_of(b);
                        if (!(na > 0 && nb > 0)) return false;
                        for (int c = 0; c + 1 < C; ++c)
                          d[c] = a.cells[static_cast<std::size_t>(c)] / na - b.cells[static_cast<std::size_t>(c)] / nb;
                        return true;
                      },
                      C - 1, true});
  paired.push_back({"power", "log E[X^2] and log E[v^2] (v the lens velocity; E[Y^2] is the mean power)",
                    [&](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
                      const double na = rows_of(a), nb = rows_of(b);
                      if (!(na > 0 && nb > 0 && a.sx2 > 0 && b.sx2 > 0 && a.sv2 > 0 && b.sv2 > 0)) return false;
                      d[0] = std::log((a.sx2 / na) / (b.sx2 / nb));
                      d[1] = std::log((a.sv2 / na) / (b.sv2 / nb));
                      return true;
                    },
                    2, true});
  if (W >= 2)
    paired.push_back({"wells", "probability per well of the model's potential and the well-to-well transition rate",
                      [&, W](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
                        const double na = rows_of(a), nb = rows_of(b);
                        if (!(na > 0 && nb > 0 && a.duration > 0 && b.duration > 0)) return false;
                        for (int w = 0; w + 1 < W; ++w)
                          d[w] = a.well_rows[static_cast<std::size_t>(w)] / na - b.well_rows[static_cast<std::size_t>(w)] / nb;
                        d[W - 1] = a.transitions / a.duration - b.transitions / b.duration;
                        return true;
                      },
                      W, true});
  paired.push_back({"acf", "log power spectrum of x in log-spaced frequency bands (the Fourier pair of its ACF)",
                    spectrum_fn(edges_x, false), static_cast<int>(edges_x.size()) - 1, true});
  lap(res, "tests_setup");

  // ---- the model's parameter uncertainty: refit on pseudo-data, resimulate with common random numbers
  std::vector<ExtraCovariance> extra(paired.size());
  int draws = 0;
  {
    const bool fitted = !model.drift_stderr.empty() || !model.diffusion_stderr.empty();
    const bool use = opt.parameter_uncertainty == ParameterUncertainty::On ||
                     (opt.parameter_uncertainty == ParameterUncertainty::Auto && fitted);
    if (use) {
      // pseudo-data: twins of the first records, at most parameter_fit_samples samples
      const auto limit = static_cast<std::size_t>(opt.parameter_fit_samples);
      const Dataset sub = leading_samples(data, [&](std::size_t, const Record& r, std::size_t taken) {
        const std::size_t n = taken < limit ? std::min(r.size, limit - taken) : 0;
        return n < 64 ? kEndSelection : n;
      });
      const double scale = static_cast<double>(sub.x.size()) / static_cast<double>(res.samples);
      // the model's terms and dynamic effects (all params free) as the lens sees them; an identify
      // that cannot fit an effect throws, and the warning below says the uncertainty is not propagated
      const identify::Options io = refit_options(model, lens);
      detail::TwinSettings ps = ts;
      ps.seed = ts.seed ^ 0x5EED5EED5EEDull;
      detail::TwinSimulator pseudo_sim(model, sub, ps);
      std::vector<Eigen::MatrixXd> acc(paired.size()), acc_within(paired.size());
      std::vector<double> acc_units(paired.size(), 0.0);
      for (std::size_t k = 0; k < paired.size(); ++k) {
        acc[k] = Eigen::MatrixXd::Zero(paired[k].p, paired[k].p);
        acc_within[k] = acc[k];
      }
      Dataset pseudo, star_twin;
      std::vector<UnitStats> star(units.size());
      vehs::detail::ProgressCounter pprog(opt.progress, "parameter draws", opt.parameter_draws);
      try {
        for (int b = 0; b < opt.parameter_draws; ++b) {
          pseudo_sim.simulate(b, pseudo);
          const Model mstar = identify::identify(pseudo, io).model;
          detail::TwinSimulator star_sim(mstar, data, ts);  // same seed as twin replicate 0
          star_sim.simulate(0, star_twin);
#pragma omp parallel for schedule(dynamic, 1)
          for (long j = 0; j < static_cast<long>(units.size()); ++j) {
            const UnitSpan& sp = units[static_cast<std::size_t>(j)];
            const Record& rec = star_twin.records[sp.record];
            detail::compute_unit(setup, star_twin.x_of(rec),
                                 model.uses_drive() ? data.u_of(data.records[sp.record]) : nullptr, rec.size,
                                 rec.t0, sp, star[static_cast<std::size_t>(j)], true);
          }
          for (std::size_t k = 0; k < paired.size(); ++k) {
            if (!paired[k].parameter_sensitive) continue;
            const Eigen::MatrixXd De = unit_diffs(paired[k].f, star, rep0, paired[k].p);
            if (De.rows() < 3) continue;
            const Eigen::VectorXd e = De.colwise().mean().transpose();
            const Eigen::MatrixXd Ce = De.rowwise() - e.transpose();
            const double n = static_cast<double>(De.rows());
            acc[k] += e * e.transpose();
            acc_within[k] += (Ce.transpose() * Ce) / ((n - 1.0) * n);
            acc_units[k] += n;
          }
          ++draws;
          pprog.advance();
        }
      } catch (const std::exception& e) {
        res.warnings.push_back(std::string("the model's parameter uncertainty could not be estimated (") + e.what() +
                               "); the stationary tests ignore it");
        draws = 0;
      }
      pprog.finish();
      if (draws > 0)
        for (std::size_t k = 0; k < paired.size(); ++k) {
          if (!paired[k].parameter_sensitive) continue;
          // the refits used `scale` times the data's samples: their parameter covariance is 1/scale
          // times the data's
          ExtraCovariance ec;
          ec.second_moment = acc[k] / draws;
          ec.within = acc_within[k] / draws;
          ec.draws = draws;
          ec.units = acc_units[k] / draws;
          extra[k] = ec.scaled(scale);
        }
      res.parameter_draws = draws;
      res.parameter_fit_samples = sub.x.size();
    }
  }
  lap(res, "parameter_draws");

  for (std::size_t k = 0; k < paired.size(); ++k) {
    const Eigen::MatrixXd Dm = unit_diffs(paired[k].f, dstats, tstats, paired[k].p);
    const bool with = draws > 0 && paired[k].parameter_sensitive;
    res.components.push_back({paired[k].name, paired[k].what,
                              hotelling_zero_mean(Dm, 1e-9, with ? &extra[k] : nullptr)});
  }

  // ---- residual lines: the largest excess of the residual spectrum in ONE frequency bin (a
  // periodic force the model lacks is a line that log-spaced bands dilute). Per bin k, the paired
  // t statistic of log(P_data/P_twin) over units; the largest t is referred to the one-sided t
  // law with U − 1 degrees of freedom, Bonferroni over the bins.
  {
    Component c{"residual_lines",
                "largest excess of the whitened-residual spectrum in a single frequency bin (periodic forcing)",
                TestResult{}};
    const std::size_t K = setup.seg_r / 2 + 1;
    double best = -std::numeric_limits<double>::infinity();
    std::size_t kbest = 0;
    int used = 0, units_used = 0;
    for (std::size_t k = 1; k < K; ++k) {
      double s1 = 0.0, s2 = 0.0;
      int n = 0;
      for (std::size_t j = 0; j < Ud; ++j) {
        const auto& a = dstats[j];
        const auto& b = tstats[j];
        if (!(a.replicates > 0 && b.replicates > 0) || k >= a.rpsd.size() || k >= b.rpsd.size()) continue;
        const double va = a.rpsd[k] / a.replicates, vb = b.rpsd[k] / b.replicates;
        if (!(va > 0 && vb > 0)) continue;
        const double d = std::log(va / vb);
        s1 += d;
        s2 += d * d;
        ++n;
      }
      if (n < 3) continue;
      const double m = s1 / n, var = (s2 - n * m * m) / (n - 1.0);
      if (!(var > 0.0)) continue;
      const double tk = m / std::sqrt(var / n);
      ++used;
      units_used = std::max(units_used, n);
      if (tk > best) best = tk, kbest = k;
    }
    if (used > 0) {
      const double nu = units_used - 1.0;
      const double p1 = best > 0 ? 0.5 * t_sf_two_sided(best, nu) : 1.0 - 0.5 * t_sf_two_sided(best, nu);
      TestResult& t = c.test;
      t.available = true;
      t.units = units_used;
      t.statistic = best;
      t.dof = 1.0;
      t.p_value = std::min(1.0, p1 * used);
      t.chi2 = chi2_equivalent(t.p_value, 1.0, best * best);
      const double f = static_cast<double>(kbest) / (static_cast<double>(setup.seg_r) * dt);
      std::ostringstream os;
      os << "largest paired t of log residual spectrum = " << best << " at frequency " << f << " (angular "
         << 2.0 * M_PI * f << ", bin width " << 1.0 / (static_cast<double>(setup.seg_r) * dt) << ") over " << used
         << " bins, one-sided t(" << nu << "), Bonferroni";
      t.method = os.str();
      finish_excess(t);
    } else {
      c.test.note = "no frequency bin with enough units";
    }
    res.components.push_back(c);
  }

  // ---- quantities for the table
  {
    std::vector<double> nd(Ud), nt(Ud), xd(Ud), xt(Ud), vd(Ud), vt(Ud);
    for (std::size_t j = 0; j < Ud; ++j) {
      nd[j] = rows_of(dstats[j]);
      nt[j] = rows_of(tstats[j]);
      xd[j] = dstats[j].sx2, xt[j] = tstats[j].sx2, vd[j] = dstats[j].sv2, vt[j] = tstats[j].sv2;
    }
    auto quantity = [&](const std::string& name, const std::vector<double>& Nd, const std::vector<double>& Dd,
                        const std::vector<double>& Nt, const std::vector<double>& Dt) {
      Quantity q;
      q.name = name;
      const Ratio a = ratio_over_units(Nd, Dd), b = ratio_over_units(Nt, Dt);
      q.data = a.value, q.data_se = a.se, q.twin = b.value, q.twin_se = b.se;
      // paired jackknife z of the difference (unit-to-unit spread only)
      const double SNd = std::accumulate(Nd.begin(), Nd.end(), 0.0), SDd = std::accumulate(Dd.begin(), Dd.end(), 0.0);
      const double SNt = std::accumulate(Nt.begin(), Nt.end(), 0.0), SDt = std::accumulate(Dt.begin(), Dt.end(), 0.0);
      std::vector<double> jk(Nd.size());
      double mean = 0.0;
      for (std::size_t j = 0; j < Nd.size(); ++j) {
        jk[j] = (SNd - Nd[j]) / (SDd - Dd[j]) - (SNt - Nt[j]) / (SDt - Dt[j]);
        mean += jk[j];
      }
      mean /= static_cast<double>(Nd.size());
      double ss = 0.0;
      for (double v : jk) ss += (v - mean) * (v - mean);
      const double n = static_cast<double>(Nd.size());
      const double se = std::sqrt((n - 1.0) / n * ss);
      q.z = se > 0 ? (q.data - q.twin) / se : 0.0;
      res.quantities.push_back(q);
    };
    quantity("E[X^2]", xd, nd, xt, nt);
    quantity("E[v^2]", vd, nd, vt, nt);
    if (W >= 2) {
      std::vector<double> wd(Ud), wt(Ud), trd(Ud), trt(Ud), dud(Ud), dut(Ud);
      for (int w = 0; w < W; ++w) {
        for (std::size_t j = 0; j < Ud; ++j) {
          wd[j] = dstats[j].well_rows[static_cast<std::size_t>(w)];
          wt[j] = tstats[j].well_rows[static_cast<std::size_t>(w)];
        }
        quantity("P(well " + std::to_string(w + 1) + ", x_min = " + fmt(res.wells[static_cast<std::size_t>(w)].x_min, 3) + ")",
                 wd, nd, wt, nt);
      }
      for (std::size_t j = 0; j < Ud; ++j) {
        trd[j] = dstats[j].transitions, trt[j] = tstats[j].transitions;
        dud[j] = dstats[j].duration, dut[j] = tstats[j].duration;
      }
      quantity("transition rate (per time unit)", trd, dud, trt, dut);
    }
  }
  lap(res, "tests");

  // ================================================================== curves for the report
  {
    // p(x)
    Curve& c = res.px;
    const double w = (setup.hx_hi - setup.hx_lo) / setup.hx_n;
    std::vector<double> nd(Ud), nt(Ud);
    for (std::size_t j = 0; j < Ud; ++j) {
      nd[j] = std::accumulate(dstats[j].cells.begin(), dstats[j].cells.end(), 0.0) * w;
      nt[j] = std::accumulate(tstats[j].cells.begin(), tstats[j].cells.end(), 0.0) * w;
    }
    std::vector<double> hd(Ud), ht(Ud), pooled_d(static_cast<std::size_t>(setup.hx_n)), pooled_t(pooled_d.size());
    for (int b = 0; b < setup.hx_n; ++b) {
      for (std::size_t j = 0; j < Ud; ++j) {
        hd[j] = dstats[j].hx[static_cast<std::size_t>(b)];
        ht[j] = tstats[j].hx[static_cast<std::size_t>(b)];
      }
      const Ratio a = ratio_over_units(hd, nd), t = ratio_over_units(ht, nt);
      c.at.push_back(setup.hx_lo + (b + 0.5) * w);
      c.data.push_back(a.value);
      c.data_se.push_back(a.se);
      c.twin.push_back(t.value);
      c.twin_se.push_back(t.se);
      pooled_d[static_cast<std::size_t>(b)] = std::accumulate(hd.begin(), hd.end(), 0.0);
      pooled_t[static_cast<std::size_t>(b)] = std::accumulate(ht.begin(), ht.end(), 0.0);
    }
    res.hellinger_px = hellinger_distance(pooled_d, pooled_t);
    if (rep_hx.size() >= 2) res.hellinger_px_null = hellinger_distance(rep_hx[0], rep_hx[1]);
    // p(x, v)
    res.pxy_nx = setup.hxy_nx;
    res.pxy_nv = setup.hxy_nv;
    res.pxy_x_lo = setup.hxy_x_lo, res.pxy_x_hi = setup.hxy_x_hi;
    res.pxy_v_lo = setup.hxy_v_lo, res.pxy_v_hi = setup.hxy_v_hi;
    std::vector<double> sd(static_cast<std::size_t>(setup.hxy_nx * setup.hxy_nv), 0.0), st = sd;
    for (std::size_t j = 0; j < Ud; ++j)
      for (std::size_t b = 0; b < sd.size(); ++b) sd[b] += dstats[j].hxy[b], st[b] += tstats[j].hxy[b];
    res.hellinger_pxy = hellinger_distance(sd, st);
    if (rep_hxy.size() >= 2) res.hellinger_pxy_null = hellinger_distance(rep_hxy[0], rep_hxy[1]);
    const double area = (setup.hxy_x_hi - setup.hxy_x_lo) / setup.hxy_nx * (setup.hxy_v_hi - setup.hxy_v_lo) / setup.hxy_nv;
    double totd = 0.0, tott = 0.0;
    for (std::size_t j = 0; j < Ud; ++j) {
      totd += std::accumulate(dstats[j].cells.begin(), dstats[j].cells.end(), 0.0);
      tott += std::accumulate(tstats[j].cells.begin(), tstats[j].cells.end(), 0.0);
    }
    res.pxy_data.resize(sd.size());
    res.pxy_twin.resize(sd.size());
    for (std::size_t b = 0; b < sd.size(); ++b) {
      res.pxy_data[b] = sd[b] / (totd * area);
      res.pxy_twin[b] = st[b] / (tott * area);
    }
  }
  auto per_unit_curve = [&](Curve& c, std::size_t n, const std::function<double(const UnitStats&, std::size_t)>& f,
                            const std::function<double(std::size_t)>& at) {
    std::vector<double> vd(Ud), vt(Ud);
    for (std::size_t k = 0; k < n; ++k) {
      for (std::size_t j = 0; j < Ud; ++j) {
        vd[j] = f(dstats[j], k);
        vt[j] = f(tstats[j], k);
      }
      const Ratio a = mean_over_units(vd), t = mean_over_units(vt);
      c.at.push_back(at(k));
      c.data.push_back(a.value);
      c.data_se.push_back(a.se);
      c.twin.push_back(t.value);
      c.twin_se.push_back(t.se);
    }
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  per_unit_curve(res.residual_acf, setup.lags_r + 1,
                 [&](const UnitStats& s, std::size_t l) {
                   if (!(s.racf_n[l] > 0 && s.racf[0] > 0)) return nan;
                   return (s.racf[l] / s.racf_n[l]) / (s.racf[0] / s.racf_n[0]);
                 },
                 [&](std::size_t l) { return static_cast<double>(l) * dt; });
  per_unit_curve(res.x_acf, setup.lags_x + 1,
                 [&](const UnitStats& s, std::size_t l) { return s.replicates > 0 ? s.xacf[l] / s.replicates : nan; },
                 [&](std::size_t l) { return static_cast<double>(l) * setup.dt_x(); });
  // spectra on ~80 log-spaced display bands
  auto display_spectrum = [&](Curve& c, bool residual) {
    const std::size_t seg = residual ? setup.seg_r : setup.seg_x;
    const auto edges = log_bands(seg / 2, 80);
    per_unit_curve(c, edges.size() - 1,
                   [&](const UnitStats& s, std::size_t b) {
                     const auto& p = residual ? s.rpsd : s.xpsd;
                     if (!(s.replicates > 0)) return nan;
                     const double v = band_mean(p, edges[b], edges[b + 1]) / s.replicates;
                     return v > 0 ? v : nan;
                   },
                   [&](std::size_t b) {
                     const double k = std::sqrt(static_cast<double>(edges[b]) * static_cast<double>(edges[b + 1] - 1));
                     return k / (static_cast<double>(seg) * (residual ? dt : setup.dt_x()));
                   });
  };
  display_spectrum(res.residual_psd, true);
  display_spectrum(res.x_psd, false);

  // ---- FPK reference
  if (opt.fpk && fm_ptr) {
    try {
      fpk::GridRequest req;
      req.grid.x.n = opt.fpk_cells;
      req.grid.y.n = opt.fpk_cells;
      const fpk::StationaryResult st =
          fpk::solve_with_domain(*fm_ptr, req, fpk::SolveOptions{});
      const auto& g = st.grid;
      for (double xq : res.px.at) {
        const double fi = (xq - g.x.min) / g.x.h() - 0.5;
        const int i = static_cast<int>(std::floor(fi));
        double v = 0.0;
        if (i >= 0 && i + 1 < g.x.n) {
          const double t = fi - i;
          v = (1 - t) * st.marginal_x[static_cast<std::size_t>(i)] + t * st.marginal_x[static_cast<std::size_t>(i) + 1];
        }
        res.px.reference.push_back(v);
      }
      res.quantities[0].reference = st.moments.exx;
      res.quantities[1].reference = st.moments.eyy;
      res.fpk_note = "stationary FPK of the model on " + std::to_string(g.x.n) + " x " + std::to_string(g.y.n) +
                     " cells over x in [" + fmt(g.x.min) + ", " + fmt(g.x.max) + "], y in [" + fmt(g.y.min) + ", " +
                     fmt(g.y.max) + "]";
    } catch (const Error& e) {
      res.fpk_note = std::string("the stationary FPK of the model could not be solved: ") + e.what();
    }
  } else if (!opt.fpk) {
    res.fpk_note = "FPK reference switched off";
  }
  lap(res, "fpk_reference");


  // ---- suspects
  Dataset sub;  // the suspects' data when limited by suspect_samples
  bool limited = false;
  SuspectOptions suspect_options = opt.suspects;
  suspect_options.progress = opt.progress;
  if (opt.suspects.enabled) {
    if (opt.suspect_samples > 0.0 && static_cast<double>(data.total_samples()) > opt.suspect_samples) {
      // whole records, in order, up to suspect_samples samples (at least min_blocks records)
      limited = true;
      sub = leading_samples(data, [&](std::size_t i, const Record& r, std::size_t taken) {
        const bool full = static_cast<double>(taken + r.size) > opt.suspect_samples &&
                          i >= static_cast<std::size_t>(opt.suspects.min_blocks);
        return full ? kEndSelection : r.size;
      });
      res.suspects = rank_suspects(model, sub, lens, suspect_options);
      res.suspects.note += (res.suspects.note.empty() ? "" : " ") + std::string("suspects fitted on the first ") +
                           std::to_string(sub.records.size()) + " of " + std::to_string(data.records.size()) +
                           " records (" + std::to_string(sub.x.size()) + " samples; suspect_samples)";
    } else {
      res.suspects = rank_suspects(model, data, lens, suspect_options);
    }
    lap(res, "suspects");
  }
  // ... are also a test of the model: each is a held-out likelihood comparison with a larger model
  // (a named alternative). The largest held-out z over the tested effects, referred to the
  // one-sided t law with blocks − 1 degrees of freedom, Bonferroni over the effects.
  if (opt.suspects.enabled && res.suspects.blocks >= 3) {
    double zmax = -std::numeric_limits<double>::infinity();
    std::string which;
    int tested = 0;
    for (const auto& sp : res.suspects.ranked)
      if (std::isfinite(sp.z) && std::isfinite(sp.evidence)) {
        ++tested;
        if (sp.z > zmax) zmax = sp.z, which = sp.effect;
      }
    Component c{"suspects", "largest held-out evidence for a catalogue effect the model lacks (named alternatives)",
                TestResult{}};
    if (tested > 0) {
      const double nu = res.suspects.blocks - 1.0;
      const double p1 = zmax > 0 ? 0.5 * t_sf_two_sided(zmax, nu) : 1.0 - 0.5 * t_sf_two_sided(zmax, nu);
      TestResult& t = c.test;
      t.available = true;
      t.units = res.suspects.blocks;
      t.statistic = zmax;
      t.dof = 1.0;
      t.p_value = std::min(1.0, p1 * tested);
      t.chi2 = chi2_equivalent(t.p_value, 1.0, zmax * zmax);
      t.method = "largest held-out z = " + fmt(zmax) + " (" + which + ") over " + std::to_string(tested) +
                 " tested effects, one-sided t(" + fmt(nu) + "), Bonferroni";
      finish_excess(t);
    } else {
      c.test.note = "no effect could be tested";
    }
    res.components.push_back(c);
  }
  // ================================================================== verdict and score
  int available = 0;
  for (const auto& c : res.components) available += c.test.available;
  res.threshold = available > 0 ? opt.alpha / available : opt.alpha;
  bool bad = false;
  res.score = 0.0;
  for (const auto& c : res.components)
    if (c.test.available) {
      bad = bad || c.test.p_value < res.threshold;
      res.score += c.test.excess;
      res.score_expected_adequate += chi2_sf(c.test.dof, c.test.dof + 2.0) - chi2_sf(c.test.dof, c.test.dof);
    }
  res.verdict = bad ? "inadequate" : "adequate";
  if (available == 0) res.warnings.push_back("no test could be computed: the verdict rests on nothing");
  if (bad && opt.suspects.enabled && opt.suspects.confirm) {
    confirm_contenders(model, limited ? sub : data, lens, opt, res.suspects);
    lap(res, "suspects_confirmation");
  }
  // a suspect is only claimed when the model is found inadequate
  for (auto& sp : res.suspects.ranked) sp.significant = sp.held_out_significant && bad;
  res.timings.emplace_back("total", std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count());
  return res;
}

}  // namespace vehs::diagnose
