// The paired components of a diagnosis: per-unit difference vectors data − twins of the residual
// shapes, the residual spectrum, p(x, v̂) cells, the power, the wells and the spectrum of x.
#include <cmath>
#include <numeric>

#include "comparison.hpp"
#include "unit_math.hpp"

namespace vehs::diagnose::detail {

Eigen::MatrixXd unit_differences(const DiffFn& f, const std::vector<UnitStats>& A, const std::vector<UnitStats>& B, int p) {
  std::vector<Eigen::VectorXd> rows;
  Eigen::VectorXd d(p);
  for (std::size_t j = 0; j < A.size(); ++j)
    if (f(A[j], B[j], d)) rows.push_back(d);
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows.size()), p);
  for (std::size_t i = 0; i < rows.size(); ++i) M.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
  return M;
}

std::vector<PairedStatistic> paired_statistics(const StatsSetup& setup, int U) {
  const int pmax = std::max(1, U / 4);
  const auto edges_r = log_bands(setup.seg_r / 2, std::min(12, pmax));
  const auto edges_x = log_bands(setup.seg_x / 2, std::min(12, pmax));
  auto spectrum_fn = [](const std::vector<std::size_t>& edges, bool residual) -> DiffFn {
    return [edges, residual](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
      // mean of the replicates' logs on both sides (unit_stats.hpp: a log of a mean is biased)
      const auto& pa = residual ? a.rpsd_each : a.xpsd_each;
      const auto& pb = residual ? b.rpsd_each : b.xpsd_each;
      for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
        const double dk = mean_log_band(pa, edges[k], edges[k + 1]) - mean_log_band(pb, edges[k], edges[k + 1]);
        if (!std::isfinite(dk)) return false;
        d[static_cast<Eigen::Index>(k)] = dk;
      }
      return true;
    };
  };
  const int C = setup.cells();
  const int W = setup.wells() >= 2 ? setup.wells() : 0;
  std::vector<PairedStatistic> paired;
  auto shape_fn = [](bool noise) -> DiffFn {
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
                    shape_fn(false), kDriftShape, true});
  paired.push_back({"noise_shape",
                    "mean of the squared whitened residual times polynomials of (x, v) to second order: a22 with the "
                    "wrong dependence on x or v (e.g. velocity-dependent noise)",
                    shape_fn(true), kNoiseShape, true});
  paired.push_back({"residual_spectrum",
                    "log spectrum of the whitened residuals in log-spaced frequency bands (memory, periodic forcing)",
                    spectrum_fn(edges_r, true), static_cast<int>(edges_r.size()) - 1, false});
  if (C >= 2)
    paired.push_back({"pdf", "occupation of " + std::to_string(C) + " coarse (x, v) cells (quantiles of the data)",
                      [C](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
                        const double na = rows_of(a), nb = rows_of(b);
                        if (!(na > 0 && nb > 0)) return false;
                        for (int c = 0; c + 1 < C; ++c)
                          d[c] = a.cells[static_cast<std::size_t>(c)] / na - b.cells[static_cast<std::size_t>(c)] / nb;
                        return true;
                      },
                      C - 1, true});
  paired.push_back({"power", "log E[X^2] and log E[v^2] (v the lens velocity; E[Y^2] is the mean power)",
                    [](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
                      // mean of the replicates' logs on both sides (unit_stats.hpp)
                      d[0] = mean_of(a.log_msx_each) - mean_of(b.log_msx_each);
                      d[1] = mean_of(a.log_msv_each) - mean_of(b.log_msv_each);
                      return std::isfinite(d[0]) && std::isfinite(d[1]);
                    },
                    2, true});
  if (W >= 2)
    paired.push_back({"wells", "probability per well of the model's potential and the well-to-well transition rate",
                      [W](const UnitStats& a, const UnitStats& b, Eigen::VectorXd& d) {
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
  return paired;
}

}  // namespace vehs::diagnose::detail
