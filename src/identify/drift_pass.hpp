#pragma once
// Internal: identify's first streaming pass — per-fold Gram statistics of the drift dictionary
// and the acceleration target, with the moments of the Itô and sensor-noise corrections — and
// what turns them into an estimator's quadratic contrast; residuals of a fitted drift.
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Dense>

#include "streaming.hpp"
#include "vehs/identify/regression.hpp"

namespace vehs::identify::detail {

/// Per-fold drift statistics: Gram of [φ, â], Itô moments Σ ψ ∂_vφ, and the moments of the
/// sensor-noise corrections.
struct DriftStats {
  Eigen::MatrixXd Gaug;  // (K+1)², lower triangle filled during accumulation
  Eigen::MatrixXd ito;   // P × Kv: Σ ψ_m ∂_vφ_j
  Eigen::VectorXd resp;  // Kv: Σ of the friction's response term (Dictionary::sign_ito_response)
  Eigen::MatrixXd hvv;   // Kv × Kv: Σ ∂_vφ ∂_vφᵀ
  Eigen::MatrixXd h2;    // K × Kv: Σ φ ∂²_vφᵀ
  Eigen::VectorXd dx;    // K: Σ ∂_xφ
  double n = 0.0;
  double left_out = 0.0;  // rows left out where the lens does not hold (Context::lens)
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  double v2 = 0.0;

  DriftStats() = default;
  DriftStats(int K, int P, int Kv)
      : Gaug(Eigen::MatrixXd::Zero(K + 1, K + 1)), ito(Eigen::MatrixXd::Zero(P, Kv)), resp(Eigen::VectorXd::Zero(Kv)),
        hvv(Eigen::MatrixXd::Zero(Kv, Kv)), h2(Eigen::MatrixXd::Zero(K, Kv)), dx(Eigen::VectorXd::Zero(K)) {}
  void add(const DriftStats& o) {
    Gaug += o.Gaug;
    ito += o.ito;
    resp += o.resp;
    hvv += o.hvv;
    h2 += o.h2;
    dx += o.dx;
    n += o.n;
    left_out += o.left_out;
    xmin = std::min(xmin, o.xmin);
    xmax = std::max(xmax, o.xmax);
    v2 += o.v2;
  }
};

/// Drift statistics of every fold (`ito`: the Itô moments; `noise`: the sensor-noise moments).
std::vector<DriftStats> drift_pass(const Context& cx, bool ito, bool noise, const std::vector<Span>& spans,
                                   int folds, vehs::detail::ProgressCounter* progress);

/// Drift corrections that turn the Gram statistics into the contrast of an estimator.
struct DriftCorrection {
  bool ito = false;          // −½ Σ ∂_vφ a22
  Eigen::VectorXd q;                // diffusion coefficients (full ψ library) for the Itô term
  double var_v_noise = 0.0;  // s²/(2h²): errors-in-variables variance of v̂
  double ax_cov = 0.0;       // 2s²/h²: minus the covariance of â's and x's sensor noise
};

QuadraticStats drift_quadratic(const DriftStats& s, const Dictionary& phi, const DriftCorrection& corr);

/// The drift model restricted to its support, for residuals.
struct DriftModel {
  Dictionary phiS;
  Eigen::VectorXd cS;
};

/// The drift with coefficients `c` (full dictionary) restricted to the support S.
DriftModel drift_model(const Dictionary& phi, const std::vector<int>& S, const Eigen::VectorXd& c);

/// Residuals r = â − F of rows [first, first + count) of a record (and â itself when `raw`).
void span_residuals(const Context& cx, const DriftModel& dm, const Record& rec, std::size_t first,
                    std::size_t count, std::vector<double>& r, std::vector<double>* raw);

}  // namespace vehs::identify::detail
