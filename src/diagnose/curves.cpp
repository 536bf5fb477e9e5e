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

void add_curves(const Comparison& cmp, Result& res) {
  const StatsSetup& setup = cmp.setup;
  const std::vector<UnitStats>& dstats = cmp.data_stats;
  const std::vector<UnitStats>& tstats = cmp.twin_stats;
  const auto Ud = static_cast<std::size_t>(cmp.units());
  const double dt = setup.dt;
  const auto& rep_hx = cmp.rep_hx;
  const auto& rep_hxy = cmp.rep_hxy;
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
}

}  // namespace vehs::diagnose::detail
