// The curves of a diagnosis's report, data vs twins with standard errors over units: p(x),
// p(x, v̂) and their Hellinger distances (with the twin-vs-twin reference), the ACFs and spectra
// of the residuals and of x.
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/core/statistics.hpp"

namespace vehs::diagnose::detail {

namespace {

using UnitValue = std::function<double(const UnitStats&, std::size_t)>;
using Abscissa = std::function<double(std::size_t)>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double total_cells(const UnitStats& s) { return std::accumulate(s.cells.begin(), s.cells.end(), 0.0); }

/// p(x): per-unit histograms normalised by the unit's rows (ratio over units), and the
/// Hellinger distance of the pooled histograms (with the twin-vs-twin reference).
void add_px(const Comparison& cmp, Result& res) {
  const StatsSetup& setup = cmp.setup;
  const std::size_t U = static_cast<std::size_t>(cmp.units());
  Curve& c = res.px;
  const double w = (setup.hx_hi - setup.hx_lo) / setup.hx_n;
  std::vector<double> nd(U), nt(U);
  for (std::size_t j = 0; j < U; ++j) {
    nd[j] = total_cells(cmp.data_stats[j]) * w;
    nt[j] = total_cells(cmp.twin_stats[j]) * w;
  }
  std::vector<double> hd(U), ht(U), pooled_d(static_cast<std::size_t>(setup.hx_n)), pooled_t(pooled_d.size());
  for (int b = 0; b < setup.hx_n; ++b) {
    for (std::size_t j = 0; j < U; ++j) {
      hd[j] = cmp.data_stats[j].hx[static_cast<std::size_t>(b)];
      ht[j] = cmp.twin_stats[j].hx[static_cast<std::size_t>(b)];
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
  if (cmp.rep_hx.size() >= 2) res.hellinger_px_null = hellinger_distance(cmp.rep_hx[0], cmp.rep_hx[1]);
}

/// p(x, v̂) of data and twins (densities on the setup's grid) and their Hellinger distance.
void add_pxy(const Comparison& cmp, Result& res) {
  const StatsSetup& setup = cmp.setup;
  const std::size_t U = static_cast<std::size_t>(cmp.units());
  res.pxy_nx = setup.hxy_nx;
  res.pxy_nv = setup.hxy_nv;
  res.pxy_x_lo = setup.hxy_x_lo, res.pxy_x_hi = setup.hxy_x_hi;
  res.pxy_v_lo = setup.hxy_v_lo, res.pxy_v_hi = setup.hxy_v_hi;
  std::vector<double> sd(static_cast<std::size_t>(setup.hxy_nx * setup.hxy_nv), 0.0), st = sd;
  for (std::size_t j = 0; j < U; ++j)
    for (std::size_t b = 0; b < sd.size(); ++b) sd[b] += cmp.data_stats[j].hxy[b], st[b] += cmp.twin_stats[j].hxy[b];
  res.hellinger_pxy = hellinger_distance(sd, st);
  if (cmp.rep_hxy.size() >= 2) res.hellinger_pxy_null = hellinger_distance(cmp.rep_hxy[0], cmp.rep_hxy[1]);
  const double area = (setup.hxy_x_hi - setup.hxy_x_lo) / setup.hxy_nx * (setup.hxy_v_hi - setup.hxy_v_lo) / setup.hxy_nv;
  double totd = 0.0, tott = 0.0;
  for (std::size_t j = 0; j < U; ++j) {
    totd += total_cells(cmp.data_stats[j]);
    tott += total_cells(cmp.twin_stats[j]);
  }
  res.pxy_data.resize(sd.size());
  res.pxy_twin.resize(sd.size());
  for (std::size_t b = 0; b < sd.size(); ++b) {
    res.pxy_data[b] = sd[b] / (totd * area);
    res.pxy_twin[b] = st[b] / (tott * area);
  }
}

/// A curve of n points, each the mean over units of f (data and twins) with its standard error.
void per_unit_curve(const Comparison& cmp, Curve& c, std::size_t n, const UnitValue& f, const Abscissa& at) {
  const std::size_t U = static_cast<std::size_t>(cmp.units());
  std::vector<double> vd(U), vt(U);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t j = 0; j < U; ++j) {
      vd[j] = f(cmp.data_stats[j], k);
      vt[j] = f(cmp.twin_stats[j], k);
    }
    const Ratio a = mean_over_units(vd), t = mean_over_units(vt);
    c.at.push_back(at(k));
    c.data.push_back(a.value);
    c.data_se.push_back(a.se);
    c.twin.push_back(t.value);
    c.twin_se.push_back(t.se);
  }
}

/// The residuals' or x's spectrum on ~80 log-spaced display bands.
void add_spectrum(const Comparison& cmp, Curve& c, bool residual) {
  const StatsSetup& setup = cmp.setup;
  const std::size_t seg = residual ? setup.seg_r : setup.seg_x;
  const double dt = residual ? setup.dt : setup.dt_x();
  const auto edges = log_bands(seg / 2, 80);
  per_unit_curve(
      cmp, c, edges.size() - 1,
      [&](const UnitStats& s, std::size_t b) {
        const auto& p = residual ? s.rpsd : s.xpsd;
        if (!(s.replicates > 0)) return kNaN;
        const double v = band_mean(p, edges[b], edges[b + 1]) / s.replicates;
        return v > 0 ? v : kNaN;
      },
      [&](std::size_t b) {
        const double k = std::sqrt(static_cast<double>(edges[b]) * static_cast<double>(edges[b + 1] - 1));
        return k / (static_cast<double>(seg) * dt);
      });
}

}  // namespace

void add_curves(const Comparison& cmp, Result& res) {
  const StatsSetup& setup = cmp.setup;
  add_px(cmp, res);
  add_pxy(cmp, res);
  per_unit_curve(
      cmp, res.residual_acf, setup.lags_r + 1,
      [](const UnitStats& s, std::size_t l) {
        if (!(s.racf_n[l] > 0 && s.racf[0] > 0)) return kNaN;
        return (s.racf[l] / s.racf_n[l]) / (s.racf[0] / s.racf_n[0]);
      },
      [&](std::size_t l) { return static_cast<double>(l) * setup.dt; });
  per_unit_curve(
      cmp, res.x_acf, setup.lags_x + 1,
      [](const UnitStats& s, std::size_t l) { return s.replicates > 0 ? s.xacf[l] / s.replicates : kNaN; },
      [&](std::size_t l) { return static_cast<double>(l) * setup.dt_x(); });
  add_spectrum(cmp, res.residual_psd, true);
  add_spectrum(cmp, res.x_psd, false);
}

}  // namespace vehs::diagnose::detail
