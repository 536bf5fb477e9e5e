#pragma once
// Per-unit statistics of diagnose-vehs (private): the one code path that runs on data and twins.
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "vehs/diagnose/lens.hpp"
#include "vehs/core/dataset.hpp"

namespace vehs::diagnose::detail {

/// A unit: samples [begin, end) of a record (rows are attributed by their centre sample).
struct UnitSpan {
  std::size_t record = 0;
  std::size_t begin = 0, end = 0;
};

/// Everything fixed before the statistics run (from the data only).
struct StatsSetup {
  const ModelLens* lens = nullptr;
  double dt = 0.0;
  // one-step map
  int nx = 16, nv = 16;
  double x_lo = 0, x_hi = 1, v_lo = 0, v_hi = 1;
  // coarse cells of the pdf test: interior edges
  std::vector<double> cell_x, cell_v;
  // fine histograms for the figures
  int hx_n = 80;
  double hx_lo = 0, hx_hi = 1;
  int hxy_nx = 48, hxy_nv = 48;
  double hxy_x_lo = 0, hxy_x_hi = 1, hxy_v_lo = 0, hxy_v_hi = 1;
  // wells: interior boundaries (increasing) and cores [lo, hi] per well
  std::vector<double> well_bounds;
  std::vector<double> core_lo, core_hi;
  // spectra and ACFs: the residual spectrum at the row rate (segments without overlap); x is
  // block-averaged over x_decimation samples (interval dt_x) before its spectrum and ACF
  std::size_t seg_r = 1024, seg_x = 4096;
  std::size_t lags_r = 64, lags_x = 1024;
  std::size_t x_decimation = 1;
  double dt_x() const { return dt * static_cast<double>(x_decimation); }

  // smooth shape of the residual mean and variance: projections on low-order functions of the
  // standardised state x̃ = (x − shape_xc)/shape_xs, ṽ = v/shape_vs (see shape_basis)
  double shape_xc = 0.0, shape_xs = 1.0, shape_vs = 1.0;

  int map_bins() const { return nx * nv; }
  int cells() const { return static_cast<int>((cell_x.size() + 1) * (cell_v.size() + 1)); }
  int wells() const { return static_cast<int>(core_lo.size()); }
  int map_index(double x, double v) const {
    int i = static_cast<int>((x - x_lo) / (x_hi - x_lo) * nx);
    int j = static_cast<int>((v - v_lo) / (v_hi - v_lo) * nv);
    i = i < 0 ? 0 : (i >= nx ? nx - 1 : i);
    j = j < 0 ? 0 : (j >= nv ? nv - 1 : j);
    return i * nv + j;
  }
};

/// Functions of the standardised state on which the residual mean is projected (drift shape:
/// polynomials to third order, sign(ṽ) and ṽ|ṽ| — the forms of the term-like effects) and the
/// residual square (noise shape: polynomials to second order).
inline constexpr int kDriftShape = 12, kNoiseShape = 6;
inline void shape_basis(double x, double v, double* f) {
  const double x2 = x * x, v2 = v * v;
  f[0] = 1.0, f[1] = x, f[2] = v, f[3] = x2, f[4] = x * v, f[5] = v2;
  f[6] = x2 * x, f[7] = x2 * v, f[8] = x * v2, f[9] = v2 * v;
  f[10] = v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
  f[11] = v * std::abs(v);
}

/// Additive statistics of one unit (twins: summed over replicates; `replicates` counts them).
struct UnitStats {
  double replicates = 0.0;
  // one-step map: per bin n, Σr, Σr², Σr³, Σr⁴ (layout [bin * 5 + m])
  std::vector<double> map;
  double rows = 0.0, r1 = 0.0, r2 = 0.0;
  // Σ r·f_k (k < kDriftShape) and Σ r²·f_k (k < kNoiseShape) over the rows (shape_basis)
  std::vector<double> drift_shape, noise_shape;
  double invalid_rows = 0.0;  // rows where the model's residual variance is not positive
  // residual autocovariance sums Σ r_i r_{i+l} and pair counts, l = 0..lags_r
  std::vector<double> racf, racf_n;
  // residual and x spectra: summed Welch densities (per replicate) and segment counts
  std::vector<double> rpsd, xpsd;
  // each replicate's own residual and x spectra and log mean squares of x and v: the spectrum,
  // line and power tests compare the MEAN OF THE LOGS over replicates with the data's one log. The
  // log of the MEAN of R twins is not comparable with it: by Jensen it exceeds the log of one
  // replicate by about ½·CV²·(1 − 1/R), a bias that the paired tests see at many units (an
  // adequate model judged inadequate at 288 records, acf p 8e-8 with 2 twins, 7e-28 with 8;
  // bench/results/diagnose_calibration_log.md)
  std::vector<std::vector<double>> rpsd_each, xpsd_each;
  std::vector<double> log_msx_each, log_msv_each;
  // x ACF (normalised per record span), summed over replicates
  std::vector<double> xacf;
  // coarse cells (row counts) and fine histograms
  std::vector<double> cells, hx, hxy;
  // moments over rows
  double sx2 = 0.0, sv2 = 0.0;
  // wells: rows per well, transitions between cores, duration (time)
  std::vector<double> well_rows;
  double transitions = 0.0, duration = 0.0;

  void init(const StatsSetup& s);
  void add(const UnitStats& o);
};

/// Rows of a unit's statistics (the sum of its coarse-cell counts).
inline double rows_of(const UnitStats& s) {
  double n = 0.0;
  for (double c : s.cells) n += c;
  return n;
}

/// Statistics of one unit of a record (x, optional drive u, t0 of the record). With
/// `stationary_only` only the occupation, moment, well, residual-shape and x-spectrum statistics
/// are computed (no one-step map, residual spectra, histograms or ACFs) — for the
/// parameter-uncertainty draws.
void compute_unit(const StatsSetup& s, const double* x, const double* u, std::size_t n, double t0,
                  const UnitSpan& span, UnitStats& out, bool stationary_only = false);

}  // namespace vehs::diagnose::detail
