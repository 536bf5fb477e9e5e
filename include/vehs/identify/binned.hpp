#pragma once
// Binned Kramers–Moyal estimates from the data, to draw over a fitted model: the parts of the
// drift that depend on x alone (at y = 0) and on y alone, and the diffusion, each as bin means
// with standard errors. Central differences on the model's stride k (h = k·dt):
//   v̂ = (x[i+k] − x[i−k]) / 2h,   â = (x[i+k] − 2x[i] + x[i−k]) / h².
// Partial residuals separate the two drift parts: the x-bins average â minus the model's
// y-dependent and input terms at (x, v̂, u), the v̂-bins average â minus its x-only and input
// terms; the diffusion bins average c·h·(â − b2(x, v̂, u))² with c = 3/2 for central kinematics
// (ULI) and 1 for forward data (whose noise enters one step, not a tent average), less the part
// white sensor noise of sd s adds: c·h·s²·[(1/h² − g_v/2h)² + (2/h² + g_x)² + (1/h² + g_v/2h)²]
// (g_x, g_v: the model's ∂b2/∂x and ∂b2/∂v at the row; 6s²/h⁴ at leading order). When that
// part is more than `max_noise_share` of the raw diffusion pooled over the bins, the diffusion
// bins are dropped: the noise level would have to be known better than the signal it leaves. With central kinematics â's noise covaries
// with v̂'s, which biases E[â | v̂] by ½ d(a22·p)/dv / p (Stein's lemma, as in ULI's Itô
// correction): the v̂-bins are corrected for it with the bin-edge densities and a22 of the model.
#include <vector>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"

namespace vehs::identify {

struct BinnedCurve {
  std::vector<double> at;    ///< bin centres
  std::vector<double> mean;  ///< bin means (NaN: too few rows)
  std::vector<double> se;    ///< their standard errors (rows treated as independent)
  std::vector<double> rows;
};

struct BinnedOptions {
  int bins = 40;
  double noise_sd = 0.0;            ///< white sensor noise sd on x removed from the diffusion bins
  double noise_sd_se = 0.0;         ///< its standard error (widens the diffusion bins' se)
  double max_noise_share = 0.95;    ///< pooled noise share above which the diffusion bins are dropped
};

struct BinnedEstimates {
  BinnedCurve drift_x;    ///< x-only part of b2 vs x
  BinnedCurve drift_v;    ///< y-dependent part of b2 (plus the constant) vs v̂
  BinnedCurve diffusion;  ///< a22 vs x (sensor noise removed)
  double noise_sd = 0.0;             ///< the sensor noise sd removed
  double noise_share = 0.0;          ///< its share of the raw diffusion, pooled over the bins
  int diffusion_bins_dropped = 0;    ///< bins dropped (the pooled share above max_noise_share)
};

/// Bins over the 0.5 %–99.5 % quantile range of x and v̂ (`bins` each); bins with fewer than 30
/// rows are NaN. One pass over the data; memory ∝ bins (two passes: ranges, then sums). Standard
/// errors from the spread of 20 interleaved groups of blocks of 200 strides (neighbouring rows
/// overlap and share sensor noise, so rows are not independent).
BinnedEstimates binned_estimates(const Dataset& data, const Model& model, const BinnedOptions& options);
inline BinnedEstimates binned_estimates(const Dataset& data, const Model& model, int bins = 40) {
  BinnedOptions o;
  o.bins = bins;
  return binned_estimates(data, model, o);
}

}  // namespace vehs::identify
