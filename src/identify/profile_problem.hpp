#pragma once
// Internal: the profile least-squares problem of identify's dynamic forces (impact_stop,
// harmonic_forcing, electromechanical_coupling; vehs/identify/dynamic.hpp): the effects being
// fitted (components: nonlinear parameters θ, free linear parameters as regression columns,
// fixed ones as an offset), the data with its kinematics and baseline dictionary, and the
// normal-equation moments and profile contrast at given θ.
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/identify/dictionary.hpp"

namespace vehs::identify::detail {

inline constexpr double kProfileInf = std::numeric_limits<double>::infinity();
inline constexpr std::size_t kProfileSpanRows = 1u << 15;  ///< rows per span of the profile passes

inline bool has_param(const Effect& e, const char* k) { return e.params.count(k) > 0; }

/// One dynamic effect being fitted: nonlinear parameters θ (fixed or free), free linear
/// parameters (regression columns), fixed linear parameters (a known offset).
struct Component {
  EffectId id{};
  Effect given;
  std::vector<std::string> theta_names;
  std::vector<double> theta;
  std::vector<bool> theta_free;
  std::vector<double> theta_lo, theta_hi;  // search bounds (set by search_theta)
  std::vector<std::string> beta_names;  // free linear parameters (columns)
  Eigen::VectorXd beta;                        // their fitted values

  int ncols() const { return static_cast<int>(beta_names.size()); }
};

/// The component of a requested dynamic effect (params it gives are held fixed); throws for an
/// effect identify cannot fit.
Component make_component(const Effect& e);

/// Columns (free linear parameters, n × ncols column-major with leading dimension ld) and the
/// offset (fixed linear parameters, added to `off`) of one component along a record.
void component_columns(const Component& c, const double* theta, const double* x, std::size_t n, double t0, double dt,
                       int tent_k, double* cols, std::size_t ld, double* off, std::vector<double>& scratch);

/// Cov(v_i, ε_i)/a22 for the filtered velocity v at the row centre and the noise ε of the
/// central second difference (tent kernel over [t − h, t + h]): the noise dW(r), r ∈ [t − h, t],
/// enters v(t) with weight (1 − e^{−λ(t−r)})/λ and ε with (h − (t − r))/h², so
/// J = (1/h²)∫₀ʰ (h − u)(1 − e^{−λu})/λ du = [h²/2 − h/λ + (1 − e^{−λh})/λ²]/(λh²) (→ h/6 as λh → 0).
inline double electro_noise_cov(double lambda, double h) {
  const double z = lambda * h;
  if (z < 1e-3) return h / 6.0 * (1.0 - z / 4.0);
  return (h * h / 2.0 - h / lambda - std::expm1(-z) / (lambda * lambda)) / (lambda * h * h);
}

/// The fitting problem: data, kinematics, baseline dictionary, diffusion for the Itô correction.
struct Problem {
  explicit Problem(const Dataset& d) : data(d) {}
  const Dataset& data;
  bool central = true;
  int k = 1;
  double dt = 1.0, h = 1.0;
  Dictionary phi, psi;
  Eigen::VectorXd c_base, q;
  std::vector<Component> comps;
  std::size_t lead = 1, trail = 1;
  std::shared_ptr<const struct BaseMoments> base;  ///< cached θ-independent moments
  /// (column, J): columns −v whose noise covariance with â is −a22·J (set by set_noise_cov)
  std::vector<std::pair<int, double>> noise_cov_cols;

  void set_noise_cov(const std::vector<std::vector<double>>& th) {
    noise_cov_cols.clear();
    if (!central) return;
    int col = 0;
    for (std::size_t i = 0; i < comps.size(); ++i) {
      if (comps[i].id == EffectId::ElectromechanicalCoupling && comps[i].ncols() == 1)
        noise_cov_cols.emplace_back(col, electro_noise_cov(th[i][0], h));
      col += comps[i].ncols();
    }
  }

  int K() const { return phi.size(); }
  int C() const {
    int s = 0;
    for (const auto& c : comps) s += c.ncols();
    return s;
  }
  /// Free nonlinear parameters as (component, slot).
  std::vector<std::pair<int, int>> free_theta() const {
    std::vector<std::pair<int, int>> f;
    for (std::size_t i = 0; i < comps.size(); ++i)
      for (std::size_t s = 0; s < comps[i].theta.size(); ++s)
        if (comps[i].theta_free[s]) f.emplace_back(static_cast<int>(i), static_cast<int>(s));
    return f;
  }

  /// Columns and offset of all components along record r.
  void record_columns(const std::vector<std::vector<double>>& thetas, std::size_t r, Eigen::MatrixXd& cols,
                      Eigen::VectorXd& off) const {
    const Record& rec = data.records[r];
    const std::size_t n = rec.size;
    cols.setZero(static_cast<Eigen::Index>(n), C());
    off.setZero(static_cast<Eigen::Index>(n));
    std::vector<double> scratch;
    int col = 0;
    for (std::size_t i = 0; i < comps.size(); ++i) {
      component_columns(comps[i], thetas[i].data(), data.x_of(rec), n, rec.t0, rec.dt,
                        central ? k : 0, cols.data() + static_cast<Eigen::Index>(col) * static_cast<Eigen::Index>(n), n, off.data(), scratch);
      col += comps[i].ncols();
    }
  }

  std::vector<std::vector<double>> thetas() const {
    std::vector<std::vector<double>> t;
    for (const auto& c : comps) t.push_back(c.theta);
    return t;
  }

  struct Rows {
    int m = 0;
    RowBlock b;
    std::size_t first = 0;  // sample of the first row
  };
  /// Rows starting at sample i0 (row centres), up to kBlockRows, not past `end`.
  void load(const Record& rec, std::size_t i0, std::size_t end, Rows& rw) const {
    const double* x = data.x_of(rec);
    const double* u = data.u_of(rec);
    const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, end - i0));
    rw.m = m;
    rw.first = i0;
    rw.b.m = m;
    for (int c = 0; c < m; ++c) {
      const std::size_t i = i0 + static_cast<std::size_t>(c);
      if (central) {
        const auto ks = static_cast<std::size_t>(k);
        rw.b.x[c] = x[i];
        rw.b.v[c] = (x[i + ks] - x[i - ks]) / (2.0 * h);
        rw.b.a[c] = ((x[i + ks] - x[i]) - (x[i] - x[i - ks])) / (h * h);
      } else {
        rw.b.x[c] = x[i];
        rw.b.v[c] = (x[i + 1] - x[i]) / dt;
        rw.b.a[c] = ((x[i + 2] - x[i + 1]) - (x[i + 1] - x[i])) / (dt * dt);
      }
      rw.b.u[c] = u ? u[i] : 0.0;
    }
  }
};

struct Moments {
  Eigen::MatrixXd G;
  Eigen::VectorXd b;
  double aa = 0.0, n = 0.0;
  void init(int p) {
    G = Eigen::MatrixXd::Zero(p, p);
    b = Eigen::VectorXd::Zero(p);
    aa = n = 0.0;
  }
  void add(const Moments& o) {
    G += o.G;
    b += o.b;
    aa += o.aa;
    n += o.n;
  }
};

struct SpanRef {
  std::size_t record, begin, end;  // sample range of row centres
};

/// Spans of kProfileSpanRows row centres of record r.
std::vector<SpanRef> spans_of(const Problem& P, std::size_t r);

/// Per-block evaluation of [φ, columns], the target and the Itô correction.
struct BlockEval {
  Eigen::MatrixXd Z;        // kBlockRows × (K + C)
  Eigen::VectorXd t;        // target â − offset
  Eigen::MatrixXd dv;       // kBlockRows × Kv
  Eigen::MatrixXd psiv;     // kBlockRows × P
  std::vector<double> scratch;
  Eigen::VectorXd ito;      // per row: not stored; accumulated

  void run(const Problem& P, const Problem::Rows& rw, const Eigen::MatrixXd& cols, const Eigen::VectorXd& off) {
    const int K = P.K(), C = P.C(), m = rw.m;
    if (Z.rows() != kBlockRows || Z.cols() != K + C) Z.resize(kBlockRows, K + C);
    t.resize(kBlockRows);
    scratch.resize(std::max(P.phi.scratch_size(), P.psi.scratch_size()));
    P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
    for (int j = 0; j < C; ++j)
      for (int c = 0; c < m; ++c) Z(c, K + j) = cols(static_cast<Eigen::Index>(rw.first) + c, j);
    for (int c = 0; c < m; ++c) t[c] = rw.b.a[c] - off[static_cast<Eigen::Index>(rw.first) + c];
  }
  /// Subtracts ½ Σ a22 ∂_vφ of the block from b (first K entries); returns Σ a22 over the
  /// block (0 for forward kinematics).
  double ito_terms(const Problem& P, const Problem::Rows& rw, Eigen::VectorXd& b) {
    if (!P.central) return 0.0;
    const int m = rw.m;
    const auto& vt = P.phi.velocity_terms();
    scratch.resize(std::max(P.phi.scratch_size(), P.psi.scratch_size()));
    psiv.resize(kBlockRows, P.psi.size());
    P.psi.values(rw.b, psiv.data(), kBlockRows, scratch.data());
    const Eigen::VectorXd a22 = psiv.topRows(m) * P.q;
    if (!vt.empty()) {
      dv.resize(kBlockRows, static_cast<Eigen::Index>(vt.size()));
      P.phi.d_dv(rw.b, dv.data(), kBlockRows, scratch.data());
      for (std::size_t j = 0; j < vt.size(); ++j)
        b[vt[j]] -= 0.5 * a22.dot(dv.col(static_cast<Eigen::Index>(j)).head(m));
    }
    return a22.sum();
  }
  /// Subtracts the noise covariances E[ε ζ] from b: ½ Σ a22 ∂_vφ per drift term, and for the
  /// electromechanical column −v the covariance −a22·J(λ, h) of the filtered velocity with
  /// the noise of â (see electro_noise_cov). Nothing for forward kinematics.
  void add_ito(const Problem& P, const Problem::Rows& rw, Eigen::VectorXd& b) {
    if (!P.central) return;
    const double a22_sum = ito_terms(P, rw, b);
    for (const auto& [col, J] : P.noise_cov_cols) b[P.K() + col] += J * a22_sum;
  }
};

/// θ-independent moments of the baseline terms (computed once per round).
struct BaseMoments {
  Eigen::MatrixXd G;
  Eigen::VectorXd b;  // Σ φ â − ½ Σ a22 ∂_vφ
  double aa = 0.0, n = 0.0, a22sum = 0.0;
};

BaseMoments base_moments(const Problem& P);

/// Normal-equation moments at the given nonlinear parameters: the cached baseline block plus
/// the θ-dependent cross terms, accumulated only over blocks where a column or the offset is
/// non-zero (impact stops touch a few per cent of the rows).
Moments moments(const Problem& P, const std::vector<std::vector<double>>& th);

/// Profile contrast Σ t² − bᵀG⁻¹b (infinite when the columns are degenerate); the coefficients
/// (c, β) into `coef` when given.
double profile_contrast(const Moments& M, Eigen::VectorXd* coef = nullptr);
/// The profile contrast at θ.
double contrast_at(const Problem& P, const std::vector<std::vector<double>>& th);

}  // namespace vehs::identify::detail
