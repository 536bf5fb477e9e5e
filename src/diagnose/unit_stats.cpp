#include "unit_stats.hpp"

#include <algorithm>
#include <cmath>

#include "spectra.hpp"

namespace vehs::diagnose::detail {

void UnitStats::init(const StatsSetup& s) {
  replicates = 0.0;
  map.assign(static_cast<std::size_t>(s.map_bins()) * 5, 0.0);
  rows = r1 = r2 = invalid_rows = 0.0;
  drift_shape.assign(kDriftShape, 0.0);
  noise_shape.assign(kNoiseShape, 0.0);
  racf.assign(s.lags_r + 1, 0.0);
  racf_n.assign(s.lags_r + 1, 0.0);
  rpsd.assign(s.seg_r / 2 + 1, 0.0);
  xpsd.assign(s.seg_x / 2 + 1, 0.0);
  xacf.assign(s.lags_x + 1, 0.0);
  cells.assign(static_cast<std::size_t>(s.cells()), 0.0);
  hx.assign(static_cast<std::size_t>(s.hx_n), 0.0);
  hxy.assign(static_cast<std::size_t>(s.hxy_nx * s.hxy_nv), 0.0);
  sx2 = sv2 = 0.0;
  rpsd_each.clear();
  xpsd_each.clear();
  log_msx_each.clear();
  log_msv_each.clear();
  well_rows.assign(static_cast<std::size_t>(s.wells()), 0.0);
  transitions = duration = 0.0;
}

namespace {
void add_to(std::vector<double>& a, const std::vector<double>& b) {
  for (std::size_t i = 0; i < a.size(); ++i) a[i] += b[i];
}
inline int bin_of(double v, double lo, double hi, int n) {
  if (!(v >= lo && v < hi)) return -1;
  const int i = static_cast<int>((v - lo) / (hi - lo) * n);
  return i >= n ? n - 1 : i;
}
}  // namespace

void UnitStats::add(const UnitStats& o) {
  replicates += o.replicates;
  add_to(map, o.map);
  rows += o.rows;
  r1 += o.r1;
  r2 += o.r2;
  add_to(drift_shape, o.drift_shape);
  add_to(noise_shape, o.noise_shape);
  invalid_rows += o.invalid_rows;
  add_to(racf, o.racf);
  add_to(racf_n, o.racf_n);
  add_to(rpsd, o.rpsd);
  add_to(xpsd, o.xpsd);
  add_to(xacf, o.xacf);
  add_to(cells, o.cells);
  add_to(hx, o.hx);
  add_to(hxy, o.hxy);
  sx2 += o.sx2;
  sv2 += o.sv2;
  rpsd_each.insert(rpsd_each.end(), o.rpsd_each.begin(), o.rpsd_each.end());
  xpsd_each.insert(xpsd_each.end(), o.xpsd_each.begin(), o.xpsd_each.end());
  log_msx_each.insert(log_msx_each.end(), o.log_msx_each.begin(), o.log_msx_each.end());
  log_msv_each.insert(log_msv_each.end(), o.log_msv_each.begin(), o.log_msv_each.end());
  add_to(well_rows, o.well_rows);
  transitions += o.transitions;
  duration += o.duration;
}

void compute_unit(const StatsSetup& s, const double* x, const double* u, std::size_t n, double t0,
                  const UnitSpan& span, UnitStats& out, bool stationary_only) {
  out.init(s);
  out.replicates = 1.0;
  const Lens& L = s.lens->lens();
  const std::size_t i0 = std::max(span.begin, L.lead());
  const std::size_t i1 = std::min(span.end, n > L.trail() ? n - L.trail() : 0);
  if (i1 <= i0) return;
  const std::size_t m = i1 - i0;
  thread_local std::vector<double> r;
  r.assign(stationary_only ? 0 : m, 0.0);
  double f[kDriftShape];
  const int ncv = static_cast<int>(s.cell_v.size()) + 1;
  const bool wells = s.wells() >= 2;
  int last_core = -1;
  for (std::size_t i = i0; i < i1; ++i) {
    double xi, v, a;
    L.at(x, i, xi, v, a);
    bool ok = false;
    const double ri = s.lens->residual(xi, v, a, u ? u[i] : 0.0, t0 + static_cast<double>(i) * s.dt, ok);
    if (ok) {
      const double r2 = ri * ri;
      if (!stationary_only) {
        r[i - i0] = ri;
        double* mb = out.map.data() + static_cast<std::size_t>(s.map_index(xi, v)) * 5;
        mb[0] += 1.0;
        mb[1] += ri;
        mb[2] += r2;
        mb[3] += r2 * ri;
        mb[4] += r2 * r2;
      }
      out.r1 += ri;
      out.r2 += r2;
      shape_basis((xi - s.shape_xc) / s.shape_xs, v / s.shape_vs, f);
      for (int k = 0; k < kDriftShape; ++k) out.drift_shape[static_cast<std::size_t>(k)] += ri * f[k];
      for (int k = 0; k < kNoiseShape; ++k) out.noise_shape[static_cast<std::size_t>(k)] += r2 * f[k];
      out.rows += 1.0;
    } else {
      out.invalid_rows += 1.0;
    }
    const int cx = static_cast<int>(std::upper_bound(s.cell_x.begin(), s.cell_x.end(), xi) - s.cell_x.begin());
    const int cv = static_cast<int>(std::upper_bound(s.cell_v.begin(), s.cell_v.end(), v) - s.cell_v.begin());
    out.cells[static_cast<std::size_t>(cx * ncv + cv)] += 1.0;
    if (!stationary_only) {
      if (const int b = bin_of(xi, s.hx_lo, s.hx_hi, s.hx_n); b >= 0) out.hx[static_cast<std::size_t>(b)] += 1.0;
      const int bx = bin_of(xi, s.hxy_x_lo, s.hxy_x_hi, s.hxy_nx);
      const int bv = bin_of(v, s.hxy_v_lo, s.hxy_v_hi, s.hxy_nv);
      if (bx >= 0 && bv >= 0) out.hxy[static_cast<std::size_t>(bx * s.hxy_nv + bv)] += 1.0;
    }
    out.sx2 += xi * xi;
    out.sv2 += v * v;
    if (wells) {
      const int w = static_cast<int>(std::upper_bound(s.well_bounds.begin(), s.well_bounds.end(), xi) -
                                     s.well_bounds.begin());
      out.well_rows[static_cast<std::size_t>(w)] += 1.0;
      if (xi >= s.core_lo[static_cast<std::size_t>(w)] && xi <= s.core_hi[static_cast<std::size_t>(w)]) {
        if (last_core >= 0 && last_core != w) out.transitions += 1.0;
        last_core = w;
      }
    }
  }
  out.duration = static_cast<double>(m) * s.dt;
  if (!stationary_only) {
    // residual autocovariance sums and spectrum
    const std::size_t L_r = std::min(s.lags_r, m - 1);
    lag_products(r.data(), m, L_r, out.racf.data());
    for (std::size_t l = 0; l <= L_r; ++l) out.racf_n[l] = static_cast<double>(m - l);
    welch(r.data(), m, s.dt, s.seg_r, s.seg_r, out.rpsd);
    out.rpsd_each.assign(1, out.rpsd);
  }
  const double rows = rows_of(out);
  out.log_msx_each.assign(1, std::log(out.sx2 / rows));
  out.log_msv_each.assign(1, std::log(out.sv2 / rows));
  // x, block-averaged over x_decimation samples
  const std::size_t len = span.end - span.begin;
  const std::size_t md = s.x_decimation;
  thread_local std::vector<double> xd;
  xd.resize(len / md);
  for (std::size_t k = 0; k < xd.size(); ++k) {
    double acc = 0.0;
    const double* p = x + span.begin + k * md;
    for (std::size_t q = 0; q < md; ++q) acc += p[q];
    xd[k] = acc / static_cast<double>(md);
  }
  welch(xd.data(), xd.size(), s.dt_x(), s.seg_x, s.seg_x / 2, out.xpsd);
  out.xpsd_each.assign(1, out.xpsd);
  if (!stationary_only && xd.size() > s.lags_x + 1) autocorrelation_fft(xd.data(), xd.size(), s.lags_x, out.xacf);
}

}  // namespace vehs::diagnose::detail
