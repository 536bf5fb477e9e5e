#pragma once
// Internal: identify's second streaming pass — residuals of the selected drift, the weighted
// diffusion statistics per fold, the residual autocovariances (sampling diagnosis, sensor
// noise) and, for the standard errors, the per-batch score matrices.
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "drift_pass.hpp"
#include "streaming.hpp"
#include "vehs/identify/regression.hpp"

namespace vehs::identify::detail {

/// Diffusion target of row j from residuals (r[j], r[j+k]) or raw accelerations; false when
/// unavailable (the last k rows of a record for the noisy target). `uli_noise`: what a known
/// white noise of variance s² on x adds to the ULI target, 1.5h·6s²/h⁴ = 9s²/h³ (quantised
/// records, vehs/core/quantisation.hpp); the noisy target cancels any white noise itself.
inline bool diffusion_target(Target t, const Kinematics& kin, const std::vector<double>& r,
                             const std::vector<double>& raw, std::size_t j, std::size_t avail,
                             double& z, double uli_noise) {
  switch (t) {
    case Target::RawKM: z = raw[j] * raw[j] * kin.dt; return true;
    case Target::Forward: z = r[j] * r[j] * kin.dt; return true;
    case Target::Uli: z = 1.5 * kin.h * r[j] * r[j] - uli_noise; return true;
    case Target::Noisy: {
      const std::size_t jk = j + static_cast<std::size_t>(kin.k);
      if (jk >= avail) return false;
      z = (12.0 / 11.0) * kin.h * (r[j] * r[j] + 1.5 * r[j] * r[jk]);
      return true;
    }
  }
  return false;
}

/// WLS weight 1/max(a22, floor)² of the diffusion fit.
struct DiffusionWeights {
  bool weighted = false;
  Eigen::VectorXd q;          // full ψ library
  double floor = 1.0;  // lower bound of a22 in the weights
};

/// Global residual moments: Σr², Σr⁴, Σ r_j r_{j+lag}, and the long-run sums Σ r_j Σ_{l=1..L} r_{j+l}.
struct ResidualMoments {
  double n = 0.0, r2 = 0.0, r4 = 0.0, v2 = 0.0;
  std::vector<double> lag_sum, lag_n;
  double lr_sum = 0.0;  // Σ r_j Σ_{l=1..L} r_{j+l}
  double wsum = 0.0;    // Σ w_j of standardized residuals √w_j·r_j (standardized_moments; else 0)
  ResidualMoments() = default;
  explicit ResidualMoments(std::size_t nlags) : lag_sum(nlags, 0.0), lag_n(nlags, 0.0) {}
  void add(const ResidualMoments& o) {
    n += o.n;
    r2 += o.r2;
    r4 += o.r4;
    v2 += o.v2;
    lr_sum += o.lr_sum;
    wsum += o.wsum;
    for (std::size_t i = 0; i < lag_sum.size(); ++i) lag_sum[i] += o.lag_sum[i], lag_n[i] += o.lag_n[i];
  }
  double autocorrelation(std::size_t l) const {
    return lag_n[l] > 0 && r2 > 0 ? (lag_sum[l] / lag_n[l]) / (r2 / n) : 0.0;
  }
  double autocovariance(std::size_t l) const { return lag_n[l] > 0 ? lag_sum[l] / lag_n[l] : 0.0; }
  /// The autocovariance in the residuals' own units for a white (state-independent) part: that of
  /// standardized residuals over their mean weight (E[w_i^½ w_j^½ n_i n_j] ≈ E[w]·C_n(l) when the
  /// weight varies slowly over the lag).
  double white_autocovariance(std::size_t l) const { return autocovariance(l) / (wsum > 0 && n > 0 ? wsum / n : 1.0); }
  /// 1 + 2 Σ_{l=1..L} ρ_l
  double long_run_factor() const { return r2 > 0 ? 1.0 + 2.0 * lr_sum / r2 : 1.0; }
};

/// Adds the moments of residuals r[0, len) (lags reaching into r[len, avail)) to `m`.
void accumulate_moments(const std::vector<double>& r, std::size_t len, std::size_t avail,
                        const std::vector<int>& lags, int lr_window, ResidualMoments& m);

struct DiffusionSetup {
  Target target = Target::Uli;
  DriftModel dm;              // drift on its support S (residuals, drift scores)
  DiffusionWeights w;
  std::vector<int> lags;      // residual autocovariance lags (diagnostics)
  // scores for the standard errors (off in the pilot)
  bool scores = false;
  bool ito = false;           // drift score has −½ ∂_vφ a22
  bool noise = false;         // drift score has the sensor-noise corrections (∝ s²)
  double uli_noise = 0.0;     // a known white noise's part of the ULI target (diffusion_target)
  int block_rows = 1024;      // rows of a batch of the batch-means covariance (multiple of 256)
};

/// Width of the per-batch score matrix A_b: the stacked score of a batch is A_b·[1; q; s²]
/// with q the diffusion coefficients (full ψ library) and s² the sensor-noise variance.
inline int score_rows(const DiffusionSetup& ds, int P) { return ds.dm.phiS.size() + P; }
inline int score_cols(int P) { return P + 2; }

struct DiffusionStats {
  Eigen::MatrixXd Gaug;  // (P+1)²: Σ w [ψ, z][ψ, z]ᵀ
  double n = 0.0;
  double zsum = 0.0;  // Σ z (unweighted)
  ResidualMoments mom;
  Eigen::MatrixXd kron;  // Σ_b vec(A_b) vec(A_b)ᵀ (lower triangle)
  double batches = 0.0;
  DiffusionStats() = default;
  DiffusionStats(int P, std::size_t nlags, int kron_dim)
      : Gaug(Eigen::MatrixXd::Zero(P + 1, P + 1)), mom(nlags), kron(Eigen::MatrixXd::Zero(kron_dim, kron_dim)) {}
  void add(const DiffusionStats& o) {
    Gaug += o.Gaug;
    n += o.n;
    zsum += o.zsum;
    mom.add(o.mom);
    kron += o.kron;
    batches += o.batches;
  }
  QuadraticStats quadratic() const {
    const Eigen::Index P = Gaug.rows() - 1;
    QuadraticStats q(static_cast<int>(P));
    q.G = Gaug.topLeftCorner(P, P);
    q.b = Gaug.col(P).head(P);
    q.c0 = Gaug(P, P);
    q.n = n;
    return q;
  }
};

/// The residual moments at `ds.lags` of the residuals standardized by the diffusion `w.q`
/// (√w_j·r_j, w_j = 1/max(a22(x_j, v_j), w.floor)) over the rows whose lens stencil stays where
/// the lens holds under the drift `ds.dm` (lens_mask.hpp: lens_keep, mask_holds): the lag
/// statistics of a state-dependent diffusion, whose rare large-variance rows, thrown into a
/// stiff wall, would otherwise carry the autocorrelations (pilot.cpp, issue 13). The drift is
/// refitted on those rows by weighted least squares first (the given fit is pulled by the wall).
ResidualMoments standardized_moments(const Context& cx, const DiffusionSetup& ds, const DiffusionWeights& w,
                                     const std::vector<Span>& spans);

/// Diffusion statistics of every fold.
std::vector<DiffusionStats> diffusion_pass(const Context& cx, const DiffusionSetup& ds,
                                           const std::vector<Span>& spans, int folds,
                                           vehs::detail::ProgressCounter* progress);

}  // namespace vehs::identify::detail
