#pragma once
// Binned Kramers–Moyal estimates from the data, to draw over a fitted model: the parts of the
// drift that depend on x alone (at y = 0) and on y alone, and the diffusion, each as bin means
// with standard errors. Central differences on the model's stride k (h = k·dt):
//   v̂ = (x[i+k] − x[i−k]) / 2h,   â = (x[i+k] − 2x[i] + x[i−k]) / h².
// Partial residuals separate the two drift parts: the x-bins average â minus the model's
// y-dependent terms at (x, v̂), the v̂-bins average â minus its x-only terms; the diffusion bins
// average c·h·(â − b2(x, v̂))² with c = 3/2 for central kinematics (ULI) and 1 for forward data
// (whose noise enters one step, not a tent average). With central kinematics â's noise covaries
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

struct BinnedEstimates {
  BinnedCurve drift_x;    ///< x-only part of b2 vs x
  BinnedCurve drift_v;    ///< y-dependent part of b2 (plus the constant) vs v̂
  BinnedCurve diffusion;  ///< a22 vs x
};

/// Bins over the 0.5 %–99.5 % quantile range of x and v̂ (`bins` each); bins with fewer than 30
/// rows are NaN. One pass over the data; memory ∝ bins (two passes: ranges, then sums).
BinnedEstimates binned_estimates(const Dataset& data, const Model& model, int bins = 40);

}  // namespace vehs::identify
