// The statistics setup of a diagnosis, from the data only (and the model's potential for the
// wells): the same setup serves the data and every twin.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "comparison.hpp"
#include "unit_math.hpp"
#include "vehs/core/error.hpp"

namespace vehs::diagnose::detail {

namespace {

/// The data's (x, v̂) through the lens on a thinned row grid (at most ~200 000 rows), checking
/// that the model's residual variance is positive wherever the data are.
void lens_sample(const Comparison& cmp, std::vector<double>& xs, std::vector<double>& vs) {
  const Dataset& data = cmp.data;
  const Lens& lens = cmp.lens;
  const std::size_t step = std::max<std::size_t>(1, cmp.plan.rows / 200000);
  for (const auto& r : data.records) {
    const double* x = data.x_of(r);
    const std::size_t i1 = r.size > lens.trail() ? r.size - lens.trail() : 0;
    for (std::size_t i = lens.lead(); i < i1; i += step) {
      double xi, v, a;
      lens.at(x, i, xi, v, a);
      xs.push_back(xi);
      vs.push_back(v);
      if (!(cmp.model_lens.residual_variance(xi, v) > 0.0))
        throw Error("the model's diffusion a22 is not positive at x = " + fmt(xi) + ", v = " + fmt(v) + " (" +
                    record_name(r) + ", sample " + std::to_string(i) + "): it cannot describe data there");
    }
  }
}

/// Ranges of the map, the shape functions and the histograms, and the coarse cells of the pdf
/// test (at most U/4 dimensions), from quantiles of the data's (x, v̂).
void set_ranges(std::vector<double> a, std::vector<double> b, int U, StatsSetup& setup) {
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
  const int pmax = std::max(1, U / 4);
  int ncv = 3, ncx = std::min(6, (pmax + 1) / 3);
  if (ncx < 2) {
    ncv = 1;
    ncx = std::min(6, pmax + 1);
  }
  for (int i = 1; i < ncx; ++i) setup.cell_x.push_back(quantile(a, static_cast<double>(i) / ncx));
  for (int j = 1; j < ncv; ++j) setup.cell_v.push_back(quantile(b, static_cast<double>(j) / ncv));
}

/// Well k of the potential with its core: where U is below the midpoint between the minimum and
/// the lower interior barrier.
WellInfo well_with_core(const fpk::FpkModel& fm, const std::vector<fpk::Well>& wells, std::size_t k) {
  const fpk::Well& wl = wells[k];
  WellInfo wi;
  wi.x_min = wl.x_min;
  wi.lo = k == 0 ? -std::numeric_limits<double>::infinity() : wl.lo;
  wi.hi = k + 1 == wells.size() ? std::numeric_limits<double>::infinity() : wl.hi;
  double barrier = std::numeric_limits<double>::infinity();
  if (k > 0) barrier = std::min(barrier, fm.potential(wl.lo));
  if (k + 1 < wells.size()) barrier = std::min(barrier, fm.potential(wl.hi));
  const double level = wl.potential + 0.5 * (barrier - wl.potential);
  const double step = (wl.hi - wl.lo) / 2000.0;
  double a = wl.x_min, b = wl.x_min;
  while (a - step > wl.lo && fm.potential(a - step) < level) a -= step;
  while (b + step < wl.hi && fm.potential(b + step) < level) b += step;
  wi.core_lo = a;
  wi.core_hi = b;
  return wi;
}

/// The wells of the model's potential over the data's x range (±10 %), when there are 2 to
/// max(2, U/4) of them.
void set_wells(Comparison& cmp, const std::vector<double>& xs, Result& res) {
  try {
    cmp.fpk = std::make_unique<fpk::FpkModel>(cmp.model, "model");
  } catch (const Error& e) {
    res.fpk_note = std::string("no stationary FPK for this model: ") + e.what();
  }
  const fpk::FpkModel* fm = cmp.fpk.get();
  if (!fm) return;
  const int U = cmp.units();
  StatsSetup& setup = cmp.setup;
  const double xmin = *std::min_element(xs.begin(), xs.end()), xmax = *std::max_element(xs.begin(), xs.end());
  const double w = xmax - xmin;
  const auto wells = fpk::find_wells(*fm, xmin - 0.1 * w, xmax + 0.1 * w);
  if (wells.size() >= 2 && static_cast<int>(wells.size()) <= std::max(2, U / 4)) {
    for (std::size_t k = 0; k < wells.size(); ++k) {
      const WellInfo wi = well_with_core(*fm, wells, k);
      res.wells.push_back(wi);
      if (k > 0) setup.well_bounds.push_back(wells[k].lo);
      setup.core_lo.push_back(wi.core_lo);
      setup.core_hi.push_back(wi.core_hi);
    }
  } else if (wells.size() > 2) {
    res.warnings.push_back("the model has " + std::to_string(wells.size()) + " wells but only " + std::to_string(U) +
                           " units: the well test is skipped");
  }
}

/// Spectrum and ACF sizes: x is block-averaged so that a spectrum segment of at most 2048 block
/// means spans about a quarter of the shortest unit; the residual spectrum runs at the row rate.
void set_spectra(const Comparison& cmp, StatsSetup& setup) {
  const std::size_t min_unit_len = cmp.plan.min_unit_len, min_unit_rows = cmp.plan.min_unit_rows;
  setup.x_decimation =
      std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(static_cast<double>(min_unit_len) / 4.0 / 2048.0)));
  const std::size_t n_dec = min_unit_len / setup.x_decimation;
  setup.seg_x = std::clamp<std::size_t>(pow2_at_most(n_dec / 4), 16, 2048);
  setup.lags_x = std::max<std::size_t>(1, std::min(setup.seg_x / 2, n_dec / 2));
  setup.seg_r = std::clamp<std::size_t>(pow2_at_most(min_unit_rows / 8), 16, 8192);
  setup.lags_r =
      std::max<std::size_t>(1, std::min(static_cast<std::size_t>(cmp.options.residual_lags), min_unit_rows / 4));
}

}  // namespace

void make_setup(Comparison& cmp, Result& res) {
  StatsSetup& setup = cmp.setup;
  setup.lens = &cmp.model_lens;
  setup.dt = cmp.data.common_dt();
  setup.nx = cmp.options.map_bins_x;
  setup.nv = cmp.options.map_bins_v;
  std::vector<double> xs, vs;
  lens_sample(cmp, xs, vs);
  set_ranges(xs, vs, cmp.units(), setup);
  set_wells(cmp, xs, res);
  set_spectra(cmp, setup);
}

}  // namespace vehs::diagnose::detail
