// Identification of dynamic effects: profile least squares over their nonlinear parameters
// (see include/vehs/identify/dynamic.hpp for the method and its assumptions).
#include "vehs/identify/dynamic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include <Eigen/Dense>

#include "vehs/core/error.hpp"
#include "vehs/core/statistics.hpp"
#include "vehs/identify/dictionary.hpp"

namespace vehs::identify {

namespace {

/// Appends fitted dynamic effects (params with stderr) to the model file's "effect_params" list.
void append_effect_params(Model& model, const std::vector<Effect>& fitted) {
  nlohmann::ordered_json& ep = model.extra["effect_params"];
  if (!ep.is_array()) ep = nlohmann::ordered_json::array();
  for (const auto& e : fitted) {
    nlohmann::ordered_json j = effect_to_json(e);
    if (!j.contains("stderr")) j["stderr"] = nlohmann::ordered_json::object();
    ep.push_back(std::move(j));
  }
}


using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kSpanRows = 1u << 15;

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(5);
  os << v;
  return os.str();
}

bool has(const Effect& e, const char* k) { return e.params.count(k) > 0; }

/// ∫₀¹ z⁺ du and ∫₀¹ u·z⁺ du for z(u) = a + d·u.
inline void hinge_moments(double a, double d, double& m0, double& m1) {
  double u1 = 0.0, u2 = 1.0;
  if (d == 0.0) {
    m0 = std::max(a, 0.0);
    m1 = 0.5 * m0;
    return;
  }
  const double root = -a / d;
  if (d > 0) u1 = std::clamp(root, 0.0, 1.0);
  else u2 = std::clamp(root, 0.0, 1.0);
  if (u2 <= u1) {
    m0 = m1 = 0.0;
    return;
  }
  m0 = a * (u2 - u1) + 0.5 * d * (u2 * u2 - u1 * u1);
  m1 = 0.5 * a * (u2 * u2 - u1 * u1) + d * (u2 * u2 * u2 - u1 * u1 * u1) / 3.0;
}

/// Stop force shape −(x − gp)⁺ + (−x − gn)⁺ at every sample of a record; with tent_k > 0 its
/// average over the kernel of the central second difference at stride tent_k (weights
/// (k − |s|)/k² over s ∈ [−k, k] samples, x linear between samples), which is what the ULI
/// acceleration measures of a force that is not smooth in time.
void stop_shape(const double* x, std::size_t n, double gp, double gn, int tent_k, double* out) {
  const auto k = static_cast<std::size_t>(std::max(tent_k, 0));
  for (std::size_t i = 0; i < n; ++i) {
    if (k == 0 || i < k || i + k >= n) {
      out[i] = -std::max(x[i] - gp, 0.0) + std::max(-x[i] - gn, 0.0);
      continue;
    }
    // quick exit: the whole window inside the gaps
    double lo = x[i], hi = x[i];
    for (std::size_t j = i - k; j <= i + k; ++j) lo = std::min(lo, x[j]), hi = std::max(hi, x[j]);
    if (hi <= gp && lo >= -gn) {
      out[i] = 0.0;
      continue;
    }
    const double kk = static_cast<double>(k) * static_cast<double>(k);
    double acc = 0.0;
    for (long j = -static_cast<long>(k); j < static_cast<long>(k); ++j) {
      const double xa = x[static_cast<std::size_t>(static_cast<long>(i) + j)];
      const double xb = x[static_cast<std::size_t>(static_cast<long>(i) + j + 1)];
      const double alpha = j >= 0 ? (static_cast<double>(k) - static_cast<double>(j)) / kk
                                  : (static_cast<double>(k) + static_cast<double>(j)) / kk;
      const double beta = j >= 0 ? -1.0 / kk : 1.0 / kk;
      double m0, m1;
      hinge_moments(xa - gp, xb - xa, m0, m1);
      acc -= alpha * m0 + beta * m1;
      hinge_moments(-xa - gn, -(xb - xa), m0, m1);
      acc += alpha * m0 + beta * m1;
    }
    out[i] = acc;
  }
}

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
  VectorXd beta;                        // their fitted values

  int ncols() const { return static_cast<int>(beta_names.size()); }
};

Component make_component(const Effect& e) {
  Component c;
  c.id = e.id;
  c.given = e;
  auto nonlinear = [&](const char* name) {
    c.theta_names.emplace_back(name);
    c.theta_free.push_back(!has(e, name));
    c.theta.push_back(has(e, name) ? e.params.at(name) : 0.0);
  };
  switch (e.id) {
    case EffectId::HarmonicForcing:
      nonlinear("omega");
      if (has(e, "amplitude") && !has(e, "phase"))
        throw Error("effect 'harmonic_forcing': amplitude can only be held fixed together with phase");
      if (!has(e, "phase")) c.beta_names = {"A_cos", "B_sin"};
      else if (!has(e, "amplitude")) c.beta_names = {"amplitude"};
      break;
    case EffectId::ImpactStop:
      nonlinear("gap");
      nonlinear("gap_neg");
      if (!has(e, "k_stop")) c.beta_names = {"k_stop"};
      break;
    case EffectId::ElectromechanicalCoupling:
      nonlinear("lambda");
      if (!has(e, "coupling")) c.beta_names = {"coupling"};
      break;
    default:
      throw Error("effect '" + e.name() + "': identification of this dynamic effect is not supported yet");
  }
  c.beta = VectorXd::Zero(c.ncols());
  return c;
}

/// Columns (free linear parameters, n × ncols column-major with leading dimension ld) and the
/// offset (fixed linear parameters, added to `off`) of one component along a record.
void component_columns(const Component& c, const double* theta, const double* x, std::size_t n,
                       double t0, double dt, int tent_k, double* cols, std::size_t ld, double* off,
                       std::vector<double>& scratch) {
  const auto& g = c.given.params;
  switch (c.id) {
    case EffectId::HarmonicForcing: {
      const double w = theta[0];
      const bool fixed_phase = g.count("phase") > 0;
      const double ph = fixed_phase ? g.at("phase") : 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double arg = w * (t0 + static_cast<double>(i) * dt) + ph;
        const double co = std::cos(arg);
        if (!fixed_phase) {
          cols[i] = co;
          cols[ld + i] = std::sin(arg);
        } else if (c.ncols() == 1) {
          cols[i] = co;
        } else {
          off[i] += g.at("amplitude") * co;
        }
      }
      break;
    }
    case EffectId::ImpactStop: {
      scratch.resize(n);
      stop_shape(x, n, theta[0], theta[1], tent_k, scratch.data());
      for (std::size_t i = 0; i < n; ++i) {
        if (c.ncols() == 1) cols[i] = scratch[i];
        else off[i] += g.at("k_stop") * scratch[i];
      }
      break;
    }
    case EffectId::ElectromechanicalCoupling: {
      scratch.resize(n);
      filtered_velocity(x, n, dt, theta[0], scratch.data());
      for (std::size_t i = 0; i < n; ++i) {
        if (c.ncols() == 1) cols[i] = -scratch[i];
        else off[i] -= g.at("coupling") * scratch[i];
      }
      break;
    }
    default: break;
  }
}

/// Cov(v_i, ε_i)/a22 for the filtered velocity v at the row centre and the noise ε of the
/// central second difference (tent kernel over [t − h, t + h]): the noise dW(r), r ∈ [t − h, t],
/// enters v(t) with weight (1 − e^{−λ(t−r)})/λ and ε with (h − (t − r))/h², so
/// J = (1/h²)∫₀ʰ (h − u)(1 − e^{−λu})/λ du = [h²/2 − h/λ + (1 − e^{−λh})/λ²]/(λh²) (→ h/6 as λh → 0).
double electro_noise_cov(double lambda, double h) {
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
  VectorXd c_base, q;
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
  void record_columns(const std::vector<std::vector<double>>& thetas, std::size_t r, MatrixXd& cols,
                      VectorXd& off) const {
    const Record& rec = data.records[r];
    const std::size_t n = rec.size;
    cols.setZero(static_cast<Index>(n), C());
    off.setZero(static_cast<Index>(n));
    std::vector<double> scratch;
    int col = 0;
    for (std::size_t i = 0; i < comps.size(); ++i) {
      component_columns(comps[i], thetas[i].data(), data.x_of(rec), n, rec.t0, rec.dt,
                        central ? k : 0, cols.data() + static_cast<Index>(col) * static_cast<Index>(n), n, off.data(), scratch);
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
  MatrixXd G;
  VectorXd b;
  double aa = 0.0, n = 0.0;
  void init(int p) {
    G = MatrixXd::Zero(p, p);
    b = VectorXd::Zero(p);
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

std::vector<SpanRef> spans_of(const Problem& P, std::size_t r) {
  std::vector<SpanRef> s;
  const std::size_t n = P.data.records[r].size;
  if (n <= P.lead + P.trail) return s;
  const std::size_t b = P.lead, e = n - P.trail;
  for (std::size_t i = b; i < e; i += kSpanRows) s.push_back({r, i, std::min(e, i + kSpanRows)});
  return s;
}

/// Per-block evaluation of [φ, columns], the target and the Itô correction.
struct BlockEval {
  MatrixXd Z;        // kBlockRows × (K + C)
  VectorXd t;        // target â − offset
  MatrixXd dv;       // kBlockRows × Kv
  MatrixXd psiv;     // kBlockRows × P
  std::vector<double> scratch;
  VectorXd ito;      // per row: not stored; accumulated

  void run(const Problem& P, const Problem::Rows& rw, const MatrixXd& cols, const VectorXd& off) {
    const int K = P.K(), C = P.C(), m = rw.m;
    if (Z.rows() != kBlockRows || Z.cols() != K + C) Z.resize(kBlockRows, K + C);
    t.resize(kBlockRows);
    scratch.resize(std::max(P.phi.scratch_size(), P.psi.scratch_size()));
    P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
    for (int j = 0; j < C; ++j)
      for (int c = 0; c < m; ++c) Z(c, K + j) = cols(static_cast<Index>(rw.first) + c, j);
    for (int c = 0; c < m; ++c) t[c] = rw.b.a[c] - off[static_cast<Index>(rw.first) + c];
  }
  /// Subtracts ½ Σ a22 ∂_vφ of the block from b (first K entries); returns Σ a22 over the
  /// block (0 for forward kinematics).
  double ito_terms(const Problem& P, const Problem::Rows& rw, VectorXd& b) {
    if (!P.central) return 0.0;
    const int m = rw.m;
    const auto& vt = P.phi.velocity_terms();
    scratch.resize(std::max(P.phi.scratch_size(), P.psi.scratch_size()));
    psiv.resize(kBlockRows, P.psi.size());
    P.psi.values(rw.b, psiv.data(), kBlockRows, scratch.data());
    const VectorXd a22 = psiv.topRows(m) * P.q;
    if (!vt.empty()) {
      dv.resize(kBlockRows, static_cast<Index>(vt.size()));
      P.phi.d_dv(rw.b, dv.data(), kBlockRows, scratch.data());
      for (std::size_t j = 0; j < vt.size(); ++j)
        b[vt[j]] -= 0.5 * a22.dot(dv.col(static_cast<Index>(j)).head(m));
    }
    return a22.sum();
  }
  /// Subtracts the noise covariances E[ε ζ] from b: ½ Σ a22 ∂_vφ per drift term, and for the
  /// electromechanical column −v the covariance −a22·J(λ, h) of the filtered velocity with
  /// the noise of â (see electro_noise_cov). Nothing for forward kinematics.
  void add_ito(const Problem& P, const Problem::Rows& rw, VectorXd& b) {
    if (!P.central) return;
    const double a22_sum = ito_terms(P, rw, b);
    for (const auto& [col, J] : P.noise_cov_cols) b[P.K() + col] += J * a22_sum;
  }
};

/// Normal-equation moments at the given nonlinear parameters.
/// θ-independent moments of the baseline terms (computed once per round).
struct BaseMoments {
  MatrixXd G;
  VectorXd b;  // Σ φ â − ½ Σ a22 ∂_vφ
  double aa = 0.0, n = 0.0, a22sum = 0.0;
};

BaseMoments base_moments(const Problem& P) {
  const int K = P.K();
  const std::size_t R = P.data.records.size();
  std::vector<BaseMoments> per(R);
#pragma omp parallel for schedule(dynamic, 1)
  for (long rl = 0; rl < static_cast<long>(R); ++rl) {
    const std::size_t r = static_cast<std::size_t>(rl);
    BaseMoments& M = per[r];
    M.G = MatrixXd::Zero(K, K);
    M.b = VectorXd::Zero(K);
    Problem::Rows rw;
    BlockEval be;
    MatrixXd Z(kBlockRows, K);
    std::vector<double> scratch(std::max(P.phi.scratch_size(), P.psi.scratch_size()));
    const Record& rec = P.data.records[r];
    for (const auto& sp : spans_of(P, r))
      for (std::size_t i = sp.begin; i < sp.end; i += kBlockRows) {
        P.load(rec, i, sp.end, rw);
        const int m = rw.m;
        P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
        const auto Zm = Z.topRows(m);
        const Eigen::Map<const VectorXd> a(rw.b.a, m);
        M.G.noalias() += Zm.transpose() * Zm;
        M.b.noalias() += Zm.transpose() * a;
        M.aa += a.squaredNorm();
        M.n += m;
        M.a22sum += be.ito_terms(P, rw, M.b);
      }
  }
  BaseMoments tot;
  tot.G = MatrixXd::Zero(K, K);
  tot.b = VectorXd::Zero(K);
  for (const auto& m : per) {  // record order: independent of the thread count
    tot.G += m.G;
    tot.b += m.b;
    tot.aa += m.aa;
    tot.n += m.n;
    tot.a22sum += m.a22sum;
  }
  return tot;
}

/// Normal-equation moments at the given nonlinear parameters: the cached baseline block plus
/// the θ-dependent cross terms, accumulated only over blocks where a column or the offset is
/// non-zero (impact stops touch a few per cent of the rows).
Moments moments(const Problem& Pin, const std::vector<std::vector<double>>& th) {
  Problem P = Pin;
  P.set_noise_cov(th);
  if (!P.base) P.base = std::make_shared<const BaseMoments>(base_moments(P));
  const BaseMoments& B = *P.base;
  const int K = P.K(), C = P.C(), p = K + C;
  struct Cross {
    MatrixXd Gx, Gcc;
    VectorXd bc, bk;
    double aa = 0.0;
  };
  const std::size_t R = P.data.records.size();
  std::vector<Cross> per(R);
#pragma omp parallel for schedule(dynamic, 1)
  for (long rl = 0; rl < static_cast<long>(R); ++rl) {
    const std::size_t r = static_cast<std::size_t>(rl);
    Cross& X = per[r];
    X.Gx = MatrixXd::Zero(K, C);
    X.Gcc = MatrixXd::Zero(C, C);
    X.bc = VectorXd::Zero(C);
    X.bk = VectorXd::Zero(K);
    MatrixXd cols;
    VectorXd off;
    P.record_columns(th, r, cols, off);
    Problem::Rows rw;
    MatrixXd Z(kBlockRows, K);
    std::vector<double> scratch(P.phi.scratch_size());
    const Record& rec = P.data.records[r];
    for (const auto& sp : spans_of(P, r))
      for (std::size_t i = sp.begin; i < sp.end; i += kBlockRows) {
        const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, sp.end - i));
        const auto cb = cols.middleRows(static_cast<Index>(i), m);
        const auto ob = off.segment(static_cast<Index>(i), m);
        if ((C == 0 || cb.cwiseAbs().maxCoeff() == 0.0) && ob.cwiseAbs().maxCoeff() == 0.0) continue;
        P.load(rec, i, sp.end, rw);
        P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
        const auto Zm = Z.topRows(m);
        const Eigen::Map<const VectorXd> a(rw.b.a, m);
        const VectorXd t = a - ob;
        if (C > 0) {
          X.Gx.noalias() += Zm.transpose() * cb;
          X.Gcc.noalias() += cb.transpose() * cb;
          X.bc.noalias() += cb.transpose() * t;
        }
        X.bk.noalias() -= Zm.transpose() * ob;
        X.aa += (-2.0 * a.dot(ob) + ob.squaredNorm());
      }
  }
  Moments M;
  M.init(p);
  M.G.topLeftCorner(K, K) = B.G;
  M.b.head(K) = B.b;
  M.aa = B.aa;
  M.n = B.n;
  for (const auto& X : per) {
    M.G.block(0, K, K, C) += X.Gx;
    M.G.bottomRightCorner(C, C) += X.Gcc;
    M.b.tail(C) += X.bc;
    M.b.head(K) += X.bk;
    M.aa += X.aa;
  }
  M.G.block(K, 0, C, K) = M.G.block(0, K, K, C).transpose();
  for (const auto& [col, J] : P.noise_cov_cols) M.b[K + col] += J * B.a22sum;
  return M;
}

/// Profile contrast Σ t² − bᵀG⁻¹b (kInf when the columns are degenerate).
double profile_contrast(const Moments& M, VectorXd* coef = nullptr) {
  const Eigen::LDLT<MatrixXd> ldlt(M.G);
  if (ldlt.info() != Eigen::Success) return kInf;
  // degenerate: a column without signal (e.g. no sample beyond a gap)
  const VectorXd d = ldlt.vectorD();
  if (d.minCoeff() <= 1e-12 * std::max(d.maxCoeff(), 1e-300)) return kInf;
  const VectorXd z = ldlt.solve(M.b);
  if (coef) *coef = z;
  return M.aa - M.b.dot(z);
}

double contrast_at(const Problem& P, const std::vector<std::vector<double>>& th) {
  return profile_contrast(moments(P, th));
}

/// Golden-section minimisation of f on [a, b] (in the transformed variable).
template <class F>
double golden(F f, double a, double b, int iters) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int i = 0; i < iters; ++i) {
    if (fc < fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  return fc < fd ? c : d;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
  return v[i];
}

/// Residuals of the baseline drift (no dynamic columns) along record r, at the row centres.
std::vector<double> baseline_residuals(const Problem& P, std::size_t r) {
  const Record& rec = P.data.records[r];
  std::vector<double> res;
  Problem::Rows rw;
  std::vector<double> scratch(P.phi.scratch_size());
  MatrixXd Z(kBlockRows, P.K());
  for (const auto& sp : spans_of(P, r))
    for (std::size_t i = sp.begin; i < sp.end; i += kBlockRows) {
      P.load(rec, i, sp.end, rw);
      P.phi.values(rw.b, Z.data(), kBlockRows, scratch.data());
      const VectorXd F = Z.topRows(rw.m) * P.c_base;
      for (int c = 0; c < rw.m; ++c) res.push_back(rw.b.a[c] - F[c]);
    }
  return res;
}

struct Search {
  std::vector<double> grid;  // in the natural variable
  bool log_scale = false;
};

/// Candidate frequencies (rad/time) of the largest lines of the residual spectrum.
std::vector<double> spectral_lines(const Problem& P, int how_many, nlohmann::ordered_json& info) {
  std::size_t nmin = std::numeric_limits<std::size_t>::max();
  for (std::size_t r = 0; r < P.data.records.size(); ++r) {
    const std::size_t n = P.data.records[r].size;
    if (n > P.lead + P.trail) nmin = std::min(nmin, n - P.lead - P.trail);
  }
  std::size_t seg = 256;
  while (seg * 2 <= nmin && seg < (1u << 20)) seg *= 2;
  Spectrum total;
  for (std::size_t r = 0; r < P.data.records.size(); ++r) {
    const auto res = baseline_residuals(P, r);
    if (res.size() < seg) continue;
    accumulate_spectrum(total, welch_spectrum(res.data(), res.size(), P.dt, seg));
  }
  std::vector<double> out;
  const auto& f = total.frequency;
  const auto& S = total.density;
  if (f.size() < 16) return out;
  const double fmax = 0.25 / P.h;
  std::vector<std::pair<double, std::size_t>> peaks;
  const std::size_t W = 16;
  for (std::size_t i = 2; i + 1 < f.size(); ++i) {
    if (f[i] > fmax) break;
    if (!(S[i] >= S[i - 1] && S[i] >= S[i + 1])) continue;
    std::vector<double> nb;
    for (std::size_t j = (i > W ? i - W : 0); j < std::min(f.size(), i + W + 1); ++j)
      if (j + 3 < i || j > i + 3) nb.push_back(S[j]);
    const double med = quantile(nb, 0.5);
    if (med > 0) peaks.emplace_back(S[i] / med, i);
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  nlohmann::ordered_json lines = nlohmann::ordered_json::array();
  for (int j = 0; j < how_many && j < static_cast<int>(peaks.size()); ++j) {
    out.push_back(2.0 * kPi * f[peaks[static_cast<std::size_t>(j)].second]);
    lines.push_back({{"frequency", f[peaks[static_cast<std::size_t>(j)].second]},
                     {"peak_to_background", peaks[static_cast<std::size_t>(j)].first}});
  }
  info["spectrum_segment"] = seg;
  info["spectral_lines"] = lines;
  return out;
}

/// Time span over which a harmonic force must stay coherent.
double time_span(const Dataset& d) {
  double lo = kInf, hi = -kInf;
  for (const auto& r : d.records) {
    lo = std::min(lo, r.t0);
    hi = std::max(hi, r.t0 + static_cast<double>(r.size) * r.dt);
  }
  return hi - lo;
}

double longest_record(const Dataset& d) {
  double T = 0.0;
  for (const auto& r : d.records) T = std::max(T, static_cast<double>(r.size) * r.dt);
  return T;
}

/// Joint Newton steps on the profile contrast over all free entries (finite-difference gradient
/// and Hessian, in log λ for the time constant): coordinate-wise search converges slowly when
/// entries are coupled (both gaps share k_stop).
void newton_polish(Problem& P, const std::vector<std::pair<int, int>>& free_th, nlohmann::ordered_json& info) {
  const int n = static_cast<int>(free_th.size());
  auto is_log = [&](int j) {
    return P.comps[static_cast<std::size_t>(free_th[static_cast<std::size_t>(j)].first)].id ==
           EffectId::ElectromechanicalCoupling;
  };
  auto get = [&](int j) {
    const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
    const double v = P.comps[static_cast<std::size_t>(ci)].theta[static_cast<std::size_t>(sl)];
    return is_log(j) ? std::log(v) : v;
  };
  auto eval = [&](const VectorXd& z) {
    auto th = P.thetas();
    for (int j = 0; j < n; ++j) {
      const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
      const Component& c = P.comps[static_cast<std::size_t>(ci)];
      const double v = is_log(j) ? std::exp(z[j]) : z[j];
      if (!c.theta_lo.empty() && (v < c.theta_lo[static_cast<std::size_t>(sl)] || v > c.theta_hi[static_cast<std::size_t>(sl)]))
        return kInf;
      th[static_cast<std::size_t>(ci)][static_cast<std::size_t>(sl)] = v;
    }
    return contrast_at(P, th);
  };
  VectorXd z(n), d(n);
  for (int j = 0; j < n; ++j) {
    z[j] = get(j);
    const auto id = P.comps[static_cast<std::size_t>(free_th[static_cast<std::size_t>(j)].first)].id;
    d[j] = is_log(j) ? 0.02 : id == EffectId::HarmonicForcing ? 2.0 * kPi / (8.0 * time_span(P.data))
                                                             : 2e-3 * std::max(std::abs(z[j]), 1e-6);
  }
  double f0 = eval(z);
  int it = 0;
  for (; it < 8; ++it) {
    VectorXd gr(n);
    MatrixXd H(n, n);
    std::vector<double> fp(static_cast<std::size_t>(n)), fm(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      VectorXd a = z, b = z;
      a[i] += d[i];
      b[i] -= d[i];
      fp[static_cast<std::size_t>(i)] = eval(a);
      fm[static_cast<std::size_t>(i)] = eval(b);
      gr[i] = (fp[static_cast<std::size_t>(i)] - fm[static_cast<std::size_t>(i)]) / (2 * d[i]);
      H(i, i) = (fp[static_cast<std::size_t>(i)] - 2 * f0 + fm[static_cast<std::size_t>(i)]) / (d[i] * d[i]);
    }
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        VectorXd pp = z, mm = z;
        pp[i] += d[i], pp[j] += d[j];
        mm[i] -= d[i], mm[j] -= d[j];
        // f(+i+j) + f(−i−j) = 2f0 + d_i²H_ii + d_j²H_jj + 2 d_i d_j H_ij
        H(i, j) = H(j, i) = (eval(pp) + eval(mm) - 2 * f0 - d[i] * d[i] * H(i, i) - d[j] * d[j] * H(j, j)) /
                            (2 * d[i] * d[j]);
      }
    const Eigen::SelfAdjointEigenSolver<MatrixXd> es(H);
    if (es.eigenvalues().minCoeff() <= 0) break;  // not locally convex: keep the coordinate result
    VectorXd step = -H.ldlt().solve(gr);
    bool moved = false;
    for (double lam = 1.0; lam > 0.05; lam *= 0.5) {
      const VectorXd zn = z + lam * step;
      const double fn = eval(zn);
      if (fn < f0) {
        z = zn, f0 = fn, moved = true;
        break;
      }
    }
    if (!moved) break;
    bool small = true;
    for (int j = 0; j < n; ++j) small = small && std::abs(step[j]) < 0.05 * d[j];
    if (small) break;
  }
  for (int j = 0; j < n; ++j) {
    const auto [ci, sl] = free_th[static_cast<std::size_t>(j)];
    P.comps[static_cast<std::size_t>(ci)].theta[static_cast<std::size_t>(sl)] = is_log(j) ? std::exp(z[j]) : z[j];
  }
  info["newton_iterations"] = it;
}

/// Finds the free nonlinear parameters (grid, then golden-section refinement).
/// warm: the components carry the previous round's θ — skip the grids, refine locally.
void search_theta(Problem& P, nlohmann::ordered_json& info, bool warm) {
  const auto free_th = P.free_theta();
  if (free_th.empty()) return;
  // initial values and brackets per free entry
  std::vector<Search> searches(free_th.size());
  // quantiles of x for the gaps
  // samples of each side (positive x, |negative x|), sorted: the gaps are searched between
  // the median of a side and its largest excursion — a stop acts at the extremes, and a gap
  // near 0 would turn the stop into a stiffness term (collinear with x)
  std::vector<double> xpos, xneg;
  for (const auto& r : P.data.records) {
    const double* x = P.data.x_of(r);
    for (std::size_t i = 0; i < r.size; i += 3) (x[i] > 0 ? xpos : xneg).push_back(std::abs(x[i]));
  }
  std::sort(xpos.begin(), xpos.end());
  std::sort(xneg.begin(), xneg.end());
  auto sq = [](const std::vector<double>& v, double q) {
    if (v.empty()) return 1e-12;
    return std::max(v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))], 1e-12);
  };
  const std::vector<double> qs = {0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.93, 0.95, 0.97, 0.98, 0.99, 0.995, 0.998};

  for (auto& c : P.comps) {
    c.theta_lo.assign(c.theta.size(), 1e-12);
    c.theta_hi.assign(c.theta.size(), kInf);
    if (c.id == EffectId::ImpactStop) {
      c.theta_lo = {sq(xpos, 0.5), sq(xneg, 0.5)};
      c.theta_hi = {sq(xpos, 0.9999), sq(xneg, 0.9999)};
    }
  }
  for (std::size_t i = 0; i < (warm ? 0 : P.comps.size()); ++i) {
    Component& c = P.comps[i];
    nlohmann::ordered_json ci;
    // the grid of component i runs with the components initialised so far (later ones still
    // have placeholder parameters, e.g. ω = 0 makes the sin column vanish)
    Problem Q = P;
    Q.comps.assign(P.comps.begin(), P.comps.begin() + static_cast<long>(i) + 1);
    if (c.id == EffectId::ImpactStop) {
      // joint grid over matching quantiles of both sides
      double best = kInf;
      std::vector<double> gp, gn;
      for (double q : qs) {
        gp.push_back(sq(xpos, q));
        gn.push_back(sq(xneg, q));
      }
      std::size_t jb = 0;
      for (std::size_t j = 0; j < qs.size(); ++j) {
        auto th = Q.thetas();
        if (c.theta_free[0]) th[i][0] = gp[j];
        if (c.theta_free[1]) th[i][1] = gn[j];
        const double v = contrast_at(Q, th);
        if (v < best) best = v, jb = j;
      }
      if (c.theta_free[0]) c.theta[0] = gp[jb];
      if (c.theta_free[1]) c.theta[1] = gn[jb];
      ci["grid_quantile"] = qs[jb];
    } else if (c.id == EffectId::ElectromechanicalCoupling && c.theta_free[0]) {
      const double lo = 1.0 / longest_record(P.data), hi = 0.2 / P.h;
      double best = kInf;
      for (int j = 0; j < 24; ++j) {
        const double lam = lo * std::pow(hi / lo, j / 23.0);
        auto th = Q.thetas();
        th[i][0] = lam;
        const double v = contrast_at(Q, th);
        if (v < best) best = v, c.theta[0] = lam;
      }
      ci["grid"] = {lo, hi, 24};
    } else if (c.id == EffectId::HarmonicForcing && c.theta_free[0]) {
      const auto lines = spectral_lines(P, 3, ci);
      require(!lines.empty(), "harmonic_forcing: the residual spectrum has no line to start from");
      const double T = time_span(P.data);
      double best = kInf;
      for (double w0 : lines) {
        // scan ±1.5 Welch bins at a quarter of the coherent resolution 2π/T
        const double seg_res = 2.0 * kPi / (static_cast<double>(ci["spectrum_segment"].get<std::size_t>()) * P.dt);
        const double step = std::max(2.0 * kPi / (4.0 * T), 3.0 * seg_res / 400.0);
        for (double w = w0 - 1.5 * seg_res; w <= w0 + 1.5 * seg_res; w += step) {
          if (w <= 0) continue;
          auto th = Q.thetas();
          th[i][0] = w;
          const double v = contrast_at(Q, th);
          if (v < best) best = v, c.theta[0] = w;
        }
      }
      ci["scan_step"] = std::max(2.0 * kPi / (4.0 * T), 0.0);
    }
    info[c.given.name()] = ci;
  }

  // refinement per free entry: a scan of the bracket (the profile is rough on the scale of the
  // sample spacing for gaps), then golden section around the best scan point; two cycles when
  // there are several entries
  const int cycles = free_th.size() > 1 && !warm ? 2 : 1;
  for (int cy = 0; cy < cycles; ++cy)
    for (const auto& [ci, s] : free_th) {
      Component& c = P.comps[static_cast<std::size_t>(ci)];
      const double v0 = c.theta[static_cast<std::size_t>(s)];
      double a, b;
      int scan = 7;
      bool logs = false;
      if (c.id == EffectId::ImpactStop) {
        const double span = std::max((cy == 0 && !warm ? 0.15 : 0.03) * v0, 1e-9);
        a = std::max(v0 - span, 1e-12), b = v0 + span;
        scan = cy == 0 && !warm ? 21 : 9;
      } else if (c.id == EffectId::ElectromechanicalCoupling) {
        logs = true;
        const double lo = 1.0 / longest_record(P.data), hi = 0.2 / P.h;
        const double r = std::pow(hi / lo, 1.0 / 23.0);
        a = std::log(v0 / r), b = std::log(v0 * r);
        scan = 9;
      } else {
        const double step = 2.0 * kPi / (4.0 * time_span(P.data));
        a = v0 - 1.5 * step, b = v0 + 1.5 * step;
      }
      const double lo = c.theta_lo[static_cast<std::size_t>(s)], hi = c.theta_hi[static_cast<std::size_t>(s)];
      auto f = [&](double z) {
        const double v = logs ? std::exp(z) : z;
        if (v < lo || v > hi) return kInf;
        auto th = P.thetas();
        th[static_cast<std::size_t>(ci)][static_cast<std::size_t>(s)] = v;
        return contrast_at(P, th);
      };
      const double z0 = logs ? std::log(v0) : v0;
      double zbest = z0, fbest = f(z0);
      const double dz = (b - a) / (scan - 1);
      for (int j = 0; j < scan; ++j) {
        const double z = a + j * dz;
        const double v = f(z);
        if (v < fbest) fbest = v, zbest = z;
      }
      const double z = golden(f, zbest - dz, zbest + dz, 24);
      if (f(z) < fbest) zbest = z;
      c.theta[static_cast<std::size_t>(s)] = logs ? std::exp(zbest) : zbest;
    }
  if (free_th.size() > 1) newton_polish(P, free_th, info);
}

struct FitOut {
  VectorXd z;        // (c, β) at θ̂
  MatrixXd cov;      // of (c, β, θ_free)
  double contrast = 0.0, rows = 0.0;
  std::vector<double> beyond;  // impact: samples beyond each gap
  std::vector<std::string> term_names;  // drift terms of the engine (first K of z)
};

/// Coefficients at θ̂ and the sandwich covariance of (c, β, θ_free).
FitOut finish_fit(Problem& P) {
  FitOut out;
  auto th = P.thetas();
  P.set_noise_cov(th);
  const Moments M = moments(P, th);
  out.contrast = profile_contrast(M, &out.z);
  require(std::isfinite(out.contrast),
          "dynamic effects: the regression is degenerate at the fitted parameters (no signal of the effect)");
  out.rows = M.n;
  const int K = P.K(), C = P.C();
  for (int j = 0; j < K; ++j) out.term_names.push_back(P.phi.name(j));
  int col = K;
  for (auto& c : P.comps) {
    c.beta = out.z.segment(col, c.ncols());
    col += c.ncols();
  }
  const auto free_th = P.free_theta();
  const int T = static_cast<int>(free_th.size());
  const int p = K + C + T;
  // batch length: long against the residual correlation, ≥ 30 batches per parameter
  const std::size_t corr_len = P.central ? 3 * static_cast<std::size_t>(P.k) : 2;
  // The scores of the dynamic parameters are correlated over the slow time scales of the
  // motion (hidden-state memory 1/λ, well hopping): batches as long as ~40 per parameter allow
  // (at least 1024 rows), not just beyond the residual correlation.
  std::size_t L = std::max<std::size_t>({1024, 50 * corr_len, static_cast<std::size_t>(M.n / (40.0 * p))});
  if (M.n / static_cast<double>(L) < 30.0 * p)
    L = std::max<std::size_t>(10 * corr_len + 10, static_cast<std::size_t>(M.n / (30.0 * p)));
  const std::size_t R = P.data.records.size();
  std::vector<MatrixXd> Jr(R), Om(R);
#pragma omp parallel for schedule(dynamic, 1)
  for (long rl = 0; rl < static_cast<long>(R); ++rl) {
    const std::size_t r = static_cast<std::size_t>(rl);
    const Record& rec = P.data.records[r];
    const std::size_t n = rec.size;
    MatrixXd& J = Jr[r];
    MatrixXd& O = Om[r];
    J = MatrixXd::Zero(p, p);
    O = MatrixXd::Zero(p, p);
    MatrixXd cols;
    VectorXd off;
    P.record_columns(th, r, cols, off);
    // g = ∂f/∂θ by central differences of the force Σ β·col + off
    MatrixXd g(static_cast<Index>(n), T);
    for (int j = 0; j < T; ++j) {
      const auto [ci, s] = free_th[static_cast<std::size_t>(j)];
      const double v = th[static_cast<std::size_t>(ci)][static_cast<std::size_t>(s)];
      const double d = 1e-6 * std::max(std::abs(v), 1e-6);
      VectorXd fp, fm;
      for (int sgn = -1; sgn <= 1; sgn += 2) {
        auto t2 = th;
        t2[static_cast<std::size_t>(ci)][static_cast<std::size_t>(s)] = v + sgn * d;
        MatrixXd c2;
        VectorXd o2;
        P.record_columns(t2, r, c2, o2);
        VectorXd fcur = o2 + c2 * out.z.segment(K, C);
        (sgn < 0 ? fm : fp) = fcur;
      }
      g.col(j) = (fp - fm) / (2.0 * d);
    }
    Problem::Rows rw;
    BlockEval be;
    VectorXd batch = VectorXd::Zero(p);
    std::size_t in_batch = 0;
    MatrixXd Zg(kBlockRows, p);
    for (const auto& sp : spans_of(P, r))
      for (std::size_t i = sp.begin; i < sp.end; i += kBlockRows) {
        P.load(rec, i, sp.end, rw);
        be.run(P, rw, cols, off);
        const int m = rw.m;
        Zg.leftCols(K + C) = be.Z;
        for (int j = 0; j < T; ++j)
          for (int c = 0; c < m; ++c) Zg(c, K + C + j) = g(static_cast<Index>(rw.first) + c, j);
        const auto Zm = Zg.topRows(m);
        J.noalias() += Zm.transpose() * Zm;
        const VectorXd res = be.t.head(m) - be.Z.topRows(m) * out.z;
        VectorXd sc = Zm.transpose() * res;
        VectorXd ito = VectorXd::Zero(K + C);
        be.add_ito(P, rw, ito);  // ito = −½ Σ a22 ∂_vφ
        sc.head(K + C) += ito;
        batch += sc;
        in_batch += static_cast<std::size_t>(m);
        if (in_batch >= L) {
          O.noalias() += batch * batch.transpose();
          batch.setZero();
          in_batch = 0;
        }
      }
    if (in_batch > 0) O.noalias() += batch * batch.transpose();
  }
  MatrixXd J = MatrixXd::Zero(p, p), O = MatrixXd::Zero(p, p);
  for (std::size_t r = 0; r < R; ++r) J += Jr[r], O += Om[r];
  const MatrixXd Ji = J.fullPivLu().inverse();
  out.cov = Ji * O * Ji.transpose();
  // impact: samples beyond the gaps
  for (const auto& c : P.comps)
    if (c.id == EffectId::ImpactStop) {
      double np = 0, nn = 0;
      for (const auto& rec : P.data.records) {
        const double* x = P.data.x_of(rec);
        for (std::size_t i = 0; i < rec.size; ++i) np += x[i] > c.theta[0], nn += x[i] < -c.theta[1];
      }
      out.beyond = {np, nn};
    }
  return out;
}

double sd(const MatrixXd& cov, int i) { return cov(i, i) > 0 ? std::sqrt(cov(i, i)) : std::numeric_limits<double>::quiet_NaN(); }

/// Physical parameters and standard errors of every component.
std::vector<Effect> effects_of(const Problem& P, const FitOut& f) {
  std::vector<Effect> out;
  const int K = P.K(), C = P.C();
  const auto free_th = P.free_theta();
  int col = K;
  for (std::size_t ci = 0; ci < P.comps.size(); ++ci) {
    const Component& c = P.comps[ci];
    Effect e;
    e.id = c.id;
    e.params = c.given.params;
    for (std::size_t s = 0; s < c.theta.size(); ++s) {
      e.params[c.theta_names[s]] = c.theta[s];
      for (std::size_t j = 0; j < free_th.size(); ++j)
        if (free_th[j].first == static_cast<int>(ci) && free_th[j].second == static_cast<int>(s))
          e.stderr_[c.theta_names[s]] = sd(f.cov, K + C + static_cast<int>(j));
    }
    if (c.id == EffectId::HarmonicForcing && c.ncols() == 2) {
      const double A = c.beta[0], B = c.beta[1];
      const double R = std::hypot(A, B);
      e.params["amplitude"] = R;
      e.params["phase"] = std::atan2(-B, A);
      // delta method: ∂R = (A, B)/R, ∂φ = (B, −A)/R²
      const Eigen::Matrix2d S = f.cov.block(col, col, 2, 2);
      const Eigen::Vector2d gR(A / R, B / R), gP(B / (R * R), -A / (R * R));
      e.stderr_["amplitude"] = std::sqrt(std::max(gR.dot(S * gR), 0.0));
      e.stderr_["phase"] = std::sqrt(std::max(gP.dot(S * gP), 0.0));
    } else {
      for (int j = 0; j < c.ncols(); ++j) {
        e.params[c.beta_names[static_cast<std::size_t>(j)]] = c.beta[j];
        e.stderr_[c.beta_names[static_cast<std::size_t>(j)]] = sd(f.cov, col + j);
      }
    }
    col += c.ncols();
    if (c.id == EffectId::ImpactStop)
      require(e.params["k_stop"] > 0.0, "impact_stop: the fitted k_stop is " + fmt(e.params["k_stop"]) +
                                            " (not > 0): the data show no stops");
    if (c.id == EffectId::ElectromechanicalCoupling)
      require(e.params["coupling"] >= 0.0, "electromechanical_coupling: the fitted coupling is " +
                                               fmt(e.params["coupling"]) + " (< 0): no coupling in the data");
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<Term> terms_of(const TermList& l) {
  std::vector<Term> t;
  for (const auto& tc : l) t.push_back(tc.term);
  return t;
}

}  // namespace

bool is_dynamic(EffectId id) { return !effect_spec(id).term_like; }

bool dynamic_fit_supported(EffectId id) {
  return id == EffectId::HarmonicForcing || id == EffectId::ImpactStop || id == EffectId::ElectromechanicalCoupling ||
         id == EffectId::ColoredNoise;
}

void filtered_velocity(const double* x, std::size_t n, double dt, double lambda, double* v) {
  if (n == 0) return;
  const double z = lambda * dt;
  const double a = std::exp(-z);
  const double g = z > 1e-8 ? -std::expm1(-z) / z : 1.0 - 0.5 * z;
  v[0] = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i) v[i + 1] = a * v[i] + g * (x[i + 1] - x[i]);
}

void dynamic_force(const std::vector<Effect>& effects, const Dataset& data, const Record& r,
                   std::vector<double>& out, int tent_k) {
  out.assign(r.size, 0.0);
  const double* x = data.x_of(r);
  std::vector<double> v;
  for (const auto& e : effects) {
    switch (e.id) {
      case EffectId::HarmonicForcing: {
        const double A = e.param("amplitude"), w = e.param("omega");
        const double ph = e.params.count("phase") ? e.param("phase") : 0.0;
        for (std::size_t i = 0; i < r.size; ++i)
          out[i] += A * std::cos(w * (r.t0 + static_cast<double>(i) * r.dt) + ph);
        break;
      }
      case EffectId::ImpactStop: {
        const double k = e.param("k_stop"), gp = e.param("gap");
        const double gn = e.params.count("gap_neg") ? e.param("gap_neg") : gp;
        v.resize(r.size);
        stop_shape(x, r.size, gp, gn, tent_k, v.data());
        for (std::size_t i = 0; i < r.size; ++i) out[i] += k * v[i];
        break;
      }
      case EffectId::ElectromechanicalCoupling: {
        v.resize(r.size);
        filtered_velocity(x, r.size, r.dt, e.param("lambda"), v.data());
        const double cpl = e.param("coupling");
        for (std::size_t i = 0; i < r.size; ++i) out[i] -= cpl * v[i];
        break;
      }
      default: break;
    }
  }
}

namespace detail {

Result identify_dynamic(const Dataset& data, const Options& options) {
  for (const auto& e : options.effects)
    if (e.id == EffectId::ColoredNoise) return identify_colored(data, options);
  Options base = options;
  base.effects.clear();
  std::vector<Effect> dyn;
  for (const auto& e : options.effects) {
    if (!is_dynamic(e.id)) {
      base.effects.push_back(e);
      continue;
    }
    for (const auto& d : dyn)
      require(d.id != e.id, "effect '" + e.name() + "' is listed twice");
    dyn.push_back(e);
  }
  std::vector<Component> comps;
  for (const auto& e : dyn) comps.push_back(make_component(e));

  Result cur = identify(data, base);
  nlohmann::ordered_json info;
  std::vector<Effect> fitted;
  FitOut fit;
  std::vector<double> force(data.x.size(), 0.0);
  Result next;
  // the full drift library (with the terms of term-like effects): the first profile fit runs on
  // all of it, because a selection made without the dynamic effect can have absorbed it (high
  // powers of x standing in for the stops); later rounds use identify's selection made with the
  // fitted dynamic force subtracted
  std::vector<Term> full = options.drift_library;
  for (const auto& e : base.effects) {
    Effect unit;
    unit.id = e.id;
    for (const auto& ps : effect_spec(e.id).params) unit.params[std::string(ps.name)] = 1.0;
    for (const auto& tc : effect_terms(unit).drift)
      if (std::find(full.begin(), full.end(), tc.term) == full.end()) full.push_back(tc.term);
  }
  for (int round = 0; round < 3; ++round) {
    Problem P(data);
    P.central = cur.estimator_used == Estimator::Uli || cur.estimator_used == Estimator::Noisy;
    P.k = P.central ? cur.stride : 1;
    P.dt = data.common_dt();
    P.h = P.central ? P.k * P.dt : P.dt;
    P.lead = P.central ? static_cast<std::size_t>(P.k) : 0;
    P.trail = P.central ? static_cast<std::size_t>(P.k) : 2;
    const std::vector<Term> support = round == 0 ? full : terms_of(cur.model.drift);
    P.phi = Dictionary(support);
    P.psi = Dictionary(terms_of(cur.model.diffusion));
    P.q = VectorXd(P.psi.size());
    for (int j = 0; j < P.psi.size(); ++j) P.q[j] = cur.model.diffusion[static_cast<std::size_t>(j)].coef;
    {
      double v2 = 0, nv = 0;
      for (const auto& rec : data.records) {
        const double* x = data.x_of(rec);
        for (std::size_t i = P.lead; i + P.trail < rec.size; i += 8) {
          const double v = P.central ? (x[i + P.lead] - x[i - P.lead]) / (2 * P.h) : (x[i + 1] - x[i]) / P.dt;
          v2 += v * v, nv += 1;
        }
      }
      P.phi.set_sign_kernel_halfwidth(std::max(0.05 * std::sqrt(v2 / std::max(nv, 1.0)), 1e-300));
      // sign(y) as the tent-averaged acceleration sees it (smoothed_sign.hpp; sensor noise neglected)
      if (P.central) P.phi.set_sign_smoothing(P.h, cur.model.diffusion, 1e-300, 0.0);
    }
    P.comps = comps;
    nlohmann::ordered_json search;
    P.base = std::make_shared<const BaseMoments>(base_moments(P));
    P.c_base = P.base->G.ldlt().solve(P.base->b);  // baseline drift without the dynamic effects
    search_theta(P, search, round > 0);
    comps = P.comps;  // warm start of the next round
      fit = finish_fit(P);
    fitted = effects_of(P, fit);
    info["search"] = search;
    {
      nlohmann::ordered_json rd;
      rd["estimator"] = enum_to_string(kEstimatorNames, cur.estimator_used);
      rd["stride"] = P.k;
      std::string sup;
      for (const auto& tc : cur.model.drift) sup += (sup.empty() ? "" : ", ") + tc.term.name();
      rd["drift_terms"] = sup;
      nlohmann::ordered_json eff = nlohmann::ordered_json::array();
      for (const auto& e : fitted) eff.push_back(effect_to_json(e));
      rd["effects"] = eff;
      rd["profile_contrast"] = fit.contrast;
      info["round_" + std::to_string(round + 1)] = rd;
    }
    for (const auto& rec : data.records) {
      std::vector<double> f;
      dynamic_force(fitted, data, rec, f, P.central ? P.k : 0);
      std::copy(f.begin(), f.end(), force.begin() + static_cast<long>(rec.offset));
    }
    Options o2 = base;
    o2.known_force = &force;
    next = identify(data, o2);
    info["rounds"] = round + 1;
    const bool same = terms_of(next.model.drift) == support && next.estimator_used == cur.estimator_used &&
                      next.stride == cur.stride;
    cur = next;
    if (same) break;
  }
  Result res = std::move(cur);
  res.model.effects = fitted;
  // drift-term standard errors: the larger of identify's (conditional on the dynamic force, with
  // the diffusion coupling of the Itô correction) and the joint one of the profile fit (which
  // carries the uncertainty of the effect's parameters — e.g. damping vs electromechanical
  // coupling are strongly correlated)
  for (std::size_t j = 0; j < fit.term_names.size(); ++j) {
    auto it = res.model.drift_stderr.find(fit.term_names[j]);
    if (it == res.model.drift_stderr.end()) continue;
    const double joint = sd(fit.cov, static_cast<int>(j));
    if (std::isfinite(joint)) it->second = std::max(it->second, joint);
  }
  nlohmann::ordered_json eff = nlohmann::ordered_json::array();
  for (const auto& e : fitted) eff.push_back(effect_to_json(e));
  info["effects"] = eff;
  info["profile_contrast"] = fit.contrast;
  info["rows"] = fit.rows;
  if (!fit.beyond.empty()) info["impact_samples_beyond_gap"] = {{"positive", fit.beyond[0]}, {"negative", fit.beyond[1]}};
  info["method"] =
      "profile least squares of the Ito-corrected drift contrast over the nonlinear parameters "
      "(grid + golden section), linear parameters jointly with the drift terms; sandwich standard "
      "errors of (terms, linear, nonlinear) with batch means; then identify refits terms and "
      "diffusion with the fitted dynamic force subtracted from the target";
  res.model.extra["dynamic_fit"] = info;
  append_effect_params(res.model, fitted);
  return res;
}

}  // namespace detail


// ---------------------------------------------------------------- colored_noise (OU excitation)
namespace {

/// M = ∫ tent(u) e^{u/τ} du for the tent kernel of half-width h (unit mass): 2(cosh z − 1)/z².
double tent_exp_mean(double z) {
  if (z < 1e-4) return 1.0 + z * z / 12.0;
  return 2.0 * (std::cosh(z) - 1.0) / (z * z);
}

/// ∫∫ tent(u) tent(s) e^{−|u−s|/τ} du ds (variance factor of the tent-averaged OU), midpoint rule.
double tent_self_factor(double h, double tau) {
  constexpr int n = 200;
  const double du = 2.0 * h / n;
  std::vector<double> u(n), w(n);
  for (int i = 0; i < n; ++i) {
    u[static_cast<std::size_t>(i)] = -h + (i + 0.5) * du;
    w[static_cast<std::size_t>(i)] = (h - std::abs(u[static_cast<std::size_t>(i)])) / (h * h) * du;
  }
  double s = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      s += w[static_cast<std::size_t>(i)] * w[static_cast<std::size_t>(j)] *
           std::exp(-std::abs(u[static_cast<std::size_t>(i)] - u[static_cast<std::size_t>(j)]) / tau);
  return s;
}

/// Rows of one record for the central (ULI) kinematics at stride k.
struct ColoredRows {
  std::vector<double> x, v, a, u;  // at samples k..n−k−1 (index i − k)
};

struct ColoredFitOut {
  double tau = 0.0, intensity = 0.0, amp = 0.0, ssr = 0.0;
  bool ok = false;
};

/// Least-squares fit of C(L) = A·exp(−L·dt/τ) over lags L ∈ [L0, L1] (A closed form; τ golden
/// section in log τ). Fixed tau / intensity honoured (intensity fixes A = I·M²/(2τ)).
ColoredFitOut fit_exponential(const std::vector<double>& C, int L0, int L1, double dt, double h,
                              const Effect& given) {
  ColoredFitOut out;
  const bool tau_fixed = given.params.count("tau") > 0;
  const bool int_fixed = given.params.count("intensity") > 0;
  auto amp_of = [&](double tau, double& ssr) {
    double se = 0, ee = 0;
    for (int L = L0; L <= L1; ++L) {
      const double e = std::exp(-L * dt / tau);
      se += C[static_cast<std::size_t>(L)] * e;
      ee += e * e;
    }
    double A = ee > 0 ? se / ee : 0.0;
    if (int_fixed) {
      const double M = tent_exp_mean(h / tau);
      A = given.params.at("intensity") * M * M / (2.0 * tau);
    }
    ssr = 0;
    for (int L = L0; L <= L1; ++L) {
      const double d = C[static_cast<std::size_t>(L)] - A * std::exp(-L * dt / tau);
      ssr += d * d;
    }
    return A;
  };
  double tau;
  if (tau_fixed) {
    tau = given.params.at("tau");
  } else {
    double lo = std::log(0.5 * dt), hi = std::log(20.0 * L1 * dt);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = hi - g * (hi - lo), b = lo + g * (hi - lo), fa, fb;
    amp_of(std::exp(a), fa);
    amp_of(std::exp(b), fb);
    for (int it = 0; it < 80; ++it) {
      if (fa < fb) {
        hi = b, b = a, fb = fa, a = hi - g * (hi - lo);
        amp_of(std::exp(a), fa);
      } else {
        lo = a, a = b, fa = fb, b = lo + g * (hi - lo);
        amp_of(std::exp(b), fb);
      }
    }
    tau = std::exp(0.5 * (lo + hi));
  }
  out.tau = tau;
  out.amp = amp_of(tau, out.ssr);
  const double M = tent_exp_mean(h / tau);
  out.intensity = int_fixed ? given.params.at("intensity") : 2.0 * tau * out.amp / (M * M);
  out.ok = std::isfinite(out.tau) && out.tau > 0 && std::isfinite(out.intensity) && out.intensity > 0;
  return out;
}

}  // namespace

void colored_prediction(const Effect& colored, const TermList& drift, const TermList& diffusion,
                        const double* x, const double* u, std::size_t n, double dt, int k,
                        std::vector<double>& eta_pred) {
  eta_pred.assign(n, 0.0);
  const auto K = static_cast<std::size_t>(std::max(k, 1));
  if (n < 4 * K + 2) return;
  const double h = static_cast<double>(K) * dt;
  const double tau = colored.param("tau"), I = colored.param("intensity");
  const double s2 = I / (2.0 * tau);
  const double p1 = std::exp(-dt / tau), q1 = s2 * (1.0 - p1 * p1);
  const double pk2 = std::exp(-2.0 * h / tau);
  double m = 0.0, P = s2;
  double rfloor = 0.0;
  for (std::size_t i = K; i + K < n; ++i) {
    const double xi = x[i], v = (x[i + K] - x[i - K]) / (2 * h);
    const double a = (x[i + K] - 2 * x[i] + x[i - K]) / (h * h);
    const double r = a - evaluate(drift, xi, v, u ? u[i] : 0.0);
    double R = evaluate(diffusion, xi, v, 0.0) / dt;  // long-run variance of the ULI noise per row
    if (rfloor == 0.0) rfloor = std::max(1e-12, 1e-3 * std::abs(R));
    R = std::max(R, rfloor);
    if (i > K) {
      m *= p1;
      P = p1 * p1 * P + q1;
    }
    const double g = P / (P + R);
    m += g * (r - m);
    P *= (1.0 - g);
    if (i + 2 * K < n) eta_pred[i + 2 * K] = pk2 * m;
  }
}

namespace detail {

Result identify_colored(const Dataset& data, const Options& options) {
  Options base = options;
  base.effects.clear();
  Effect given;
  bool found = false;
  for (const auto& e : options.effects) {
    if (e.id == EffectId::ColoredNoise) {
      require(!found, "effect 'colored_noise' is listed twice");
      given = e;
      found = true;
      continue;
    }
    require(!is_dynamic(e.id), "identify: colored_noise cannot yet be combined with the dynamic effect '" +
                                   e.name() + "'");
    require(e.params.empty(), "identify: colored_noise cannot yet be combined with held-fixed parameters of '" +
                                  e.name() + "' (remove its params to fit them)");
    base.effects.push_back(e);
  }
  for (const char* key : {"tau", "intensity"})
    if (given.params.count(key))
      require(std::isfinite(given.params.at(key)) && given.params.at(key) > 0,
              std::string("effect 'colored_noise': ") + key + " must be > 0");
  // the sampling diagnosis reads a positive lag-2k residual autocorrelation as sensor noise; an
  // OU excitation produces one too (and a slow decay over further lags, which sensor noise does
  // not), so with colored_noise requested the clean-data ULI estimator is used unless the user
  // chose otherwise
  if (base.estimator == Estimator::Auto) base.estimator = Estimator::Uli;
  Result cur = identify(data, base);
  require(cur.estimator_used == Estimator::Uli,
          "identify: colored_noise needs the uli estimator (clean, densely sampled displacement); the "
          "options chose '" + enum_to_string(kEstimatorNames, cur.estimator_used) + "'");
  const int k = cur.stride;
  const auto K = static_cast<std::size_t>(k);
  const double dt = data.common_dt();
  const double h = k * dt;
  std::vector<Term> terms;
  for (const auto& tc : cur.model.drift) terms.push_back(tc.term);
  const int p = static_cast<int>(terms.size());
  require(p > 0, "identify: colored_noise needs at least one drift term");
  std::vector<Term> dterms;
  for (const auto& tc : cur.model.diffusion) dterms.push_back(tc.term);
  const int q = static_cast<int>(dterms.size());

  // rows
  std::vector<ColoredRows> rows(data.records.size());
  for (std::size_t r = 0; r < data.records.size(); ++r) {
    const Record& rec = data.records[r];
    const double* x = data.x_of(rec);
    const double* u = data.u_of(rec);
    ColoredRows& R = rows[r];
    for (std::size_t i = K; i + K < rec.size; ++i) {
      R.x.push_back(x[i]);
      R.v.push_back((x[i + K] - x[i - K]) / (2 * h));
      double a = (x[i + K] - 2 * x[i] + x[i - K]) / (h * h);
      if (options.known_force) a -= (*options.known_force)[rec.offset + i];
      R.a.push_back(a);
      R.u.push_back(u ? u[i] : 0.0);
    }
  }
  // batches: contiguous segments, at least 20 in all
  const std::size_t nrec = rows.size();
  const std::size_t per = nrec >= 20 ? 1 : (20 + nrec - 1) / nrec;
  const std::size_t nb = nrec * per;

  VectorXd c(p);
  for (int j = 0; j < p; ++j) c[j] = cur.model.drift[static_cast<std::size_t>(j)].coef;
  auto residuals = [&](const VectorXd& coef, std::vector<std::vector<double>>& res) {
    res.resize(nrec);
    for (std::size_t r = 0; r < nrec; ++r) {
      const ColoredRows& R = rows[r];
      res[r].resize(R.a.size());
      for (std::size_t i = 0; i < R.a.size(); ++i) {
        double f = 0;
        for (int j = 0; j < p; ++j) f += coef[j] * terms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], R.u[i]);
        res[r][i] = R.a[i] - f;
      }
    }
  };
  // autocovariance sums per batch up to lag Lmax (pairs whose first index lies in the batch)
  auto autocov = [&](const std::vector<std::vector<double>>& res, int Lmax, MatrixXd& S, MatrixXd& N) {
    S = MatrixXd::Zero(Lmax + 1, static_cast<Index>(nb));
    N = MatrixXd::Zero(Lmax + 1, static_cast<Index>(nb));
#pragma omp parallel for schedule(dynamic, 1)
    for (long bl = 0; bl < static_cast<long>(nb); ++bl) {
      const std::size_t r = static_cast<std::size_t>(bl) / per, pp = static_cast<std::size_t>(bl) % per;
      const auto& e = res[r];
      const std::size_t n = e.size(), b0 = n * pp / per, b1 = n * (pp + 1) / per;
      for (int L = 0; L <= Lmax; ++L) {
        double s = 0;
        const std::size_t end = std::min(b1, n > static_cast<std::size_t>(L) ? n - static_cast<std::size_t>(L) : 0);
        for (std::size_t i = b0; i < end; ++i) s += e[i] * e[i + static_cast<std::size_t>(L)];
        S(L, bl) = s;
        N(L, bl) = end > b0 ? static_cast<double>(end - b0) : 0.0;
      }
    }
  };
  std::size_t nmin = std::numeric_limits<std::size_t>::max();
  for (const auto& R : rows) nmin = std::min(nmin, R.a.size());
  require(nmin > 40 * K, "identify: colored_noise needs records of more than " + std::to_string(40 * K + 2 * K) + " samples");
  const int Lcap = static_cast<int>(std::min<std::size_t>(nmin / 8, 20000));
  const int L0 = 2 * k;

  VectorXd qc(q), qse = VectorXd::Zero(q);
  for (int j = 0; j < q; ++j) qc[j] = cur.model.diffusion[static_cast<std::size_t>(j)].coef;
  double var_eta = 0.0;
  // white diffusion: E[r²] = σ²·Q + (2/3)·a22/h  (Q: tent self-average of the OU correlation)
  auto fit_diffusion = [&](const std::vector<std::vector<double>>& res_d, const ColoredFitOut& f_d) {
  var_eta = f_d.intensity / (2.0 * f_d.tau) * tent_self_factor(h, f_d.tau);
  if (q > 0) {
    MatrixXd G = MatrixXd::Zero(q, q);
    VectorXd g = VectorXd::Zero(q);
    std::vector<VectorXd> sb(nb, VectorXd::Zero(q));
    std::vector<MatrixXd> Gb(nb, MatrixXd::Zero(q, q));
    for (std::size_t bl = 0; bl < nb; ++bl) {
      const std::size_t r = bl / per, pp = bl % per;
      const ColoredRows& R = rows[r];
      const std::size_t n = R.a.size(), b0 = n * pp / per, b1 = n * (pp + 1) / per;
      VectorXd psi(q);
      for (std::size_t i = b0; i < b1; ++i) {
        for (int j = 0; j < q; ++j) psi[j] = dterms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], 0.0);
        const double y = (res_d[r][i] * res_d[r][i] - var_eta) * 1.5 * h;
        Gb[bl].noalias() += psi * psi.transpose();
        sb[bl] += psi * y;
      }
      G += Gb[bl];
      g += sb[bl];
    }
    const Eigen::LDLT<MatrixXd> ld(G);
    qc = ld.solve(g);
    MatrixXd Om = MatrixXd::Zero(q, q);
    for (std::size_t b = 0; b < nb; ++b) {
      const VectorXd s = sb[b] - Gb[b] * qc;
      Om.noalias() += s * s.transpose();
    }
    const MatrixXd Gi = ld.solve(MatrixXd::Identity(q, q));
    const MatrixXd cov = Gi * Om * Gi.transpose();
    for (int j = 0; j < q; ++j) qse[j] = std::sqrt(std::max(cov(j, j), 0.0));
  }
  };
  std::vector<std::vector<double>> res;
  ColoredFitOut fo;
  int L1 = L0;
  MatrixXd S, N;
  nlohmann::ordered_json info, rounds = nlohmann::ordered_json::array();
  MatrixXd Jcov;
  for (int round = 0; round < 6; ++round) {
    residuals(c, res);
    // lags: grow until the autocovariance falls below 5 % of C(L0) (or the cap)
    int Lmax = std::min(Lcap, std::max(4 * L0, fo.ok ? static_cast<int>(5.0 * fo.tau / dt) : 64));
    for (;;) {
      autocov(res, Lmax, S, N);
      const VectorXd C = S.rowwise().sum().cwiseQuotient(N.rowwise().sum());
      L1 = L0;
      while (L1 < Lmax && C[L1 + 1] > 0.05 * C[L0]) ++L1;
      if (L1 < Lmax || Lmax >= Lcap) break;
      Lmax = std::min(Lcap, 2 * Lmax);
    }
    const VectorXd Cv = S.rowwise().sum().cwiseQuotient(N.rowwise().sum());
    std::vector<double> C(Cv.data(), Cv.data() + Cv.size());
    require(C[static_cast<std::size_t>(L0)] > 0 && L1 >= L0 + 2,
            "identify: colored_noise: the drift residuals show no positive autocorrelation persisting "
            "beyond the white-noise lags (C(" + fmt(L0 * dt) + " s) = " + fmt(C[static_cast<std::size_t>(L0)]) +
                ", below 5 % of it within " + std::to_string(L1 - L0 + 1) + " lags): no coloured excitation to fit");
    const double tau_prev = fo.tau;
    fo = fit_exponential(C, L0, L1, dt, h, given);
    require(fo.ok, "identify: colored_noise: the exponential fit of the residual autocovariance failed");
    rounds.push_back({{"tau", fo.tau}, {"intensity", fo.intensity}, {"lags", {L0, L1}}});
    // drift refit on the prediction errors (GLS): T_i = â_i − η̂(â)_i, Z_i = ζ_i − η̂(ζ)_i, with η̂ the
    // Kalman predictor of the OU state from rows ≤ i − 2k (linear in the filtered series, gains
    // from a22 only), plus the usual Itô correction ½·a22·∂ζ/∂v of the ULI noise
    const double s2 = fo.intensity / (2.0 * fo.tau);
    const double p1 = std::exp(-dt / fo.tau), q1 = s2 * (1.0 - p1 * p1), pk2 = std::exp(-2.0 * h / fo.tau);
    MatrixXd G = MatrixXd::Zero(p, p);
    VectorXd bvec = VectorXd::Zero(p);
    std::vector<MatrixXd> bG(nb, MatrixXd::Zero(p, p));
    std::vector<VectorXd> bb(nb, VectorXd::Zero(p));
#pragma omp parallel for schedule(dynamic, 1)
    for (long rl = 0; rl < static_cast<long>(nrec); ++rl) {
      const std::size_t r = static_cast<std::size_t>(rl);
      const ColoredRows& R = rows[r];
      const std::size_t n = R.a.size();
      MatrixXd filt(n, p + 1);  // filtered state of each series (columns: ζ_1..ζ_p, â)
      std::vector<double> Pf(n, s2);  // filter error variance after row i
      VectorXd mstate = VectorXd::Zero(p + 1), sv(p + 1), z(p), dz(p);
      double P = s2;
      for (std::size_t i = 0; i < n; ++i) {
        double a22i = 0.0;
        for (int j = 0; j < q; ++j) a22i += qc[j] * dterms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], 0.0);
        const double Rv = std::max(a22i, 1e-6 * qc.cwiseAbs().sum() + 1e-300) / dt;
        if (i > 0) {
          mstate *= p1;
          P = p1 * p1 * P + q1;
        }
        for (int j = 0; j < p; ++j) sv[j] = terms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], R.u[i]);
        sv[p] = R.a[i];
        const double g = P / (P + Rv);
        mstate += g * (sv - mstate);
        P *= 1.0 - g;
        Pf[i] = P;
        filt.row(static_cast<Index>(i)) = mstate.transpose();
        if (i < 2 * K) continue;
        // v̂_i carries η over [t_{i−k}, t_{i+k}], which the prediction from row i − 2k does not
        // see: Cov(v̂_i, e_i) ≈ 2h·P_pred (P_pred the variance of the prediction error)
        const double Ppred = pk2 * pk2 * Pf[i - 2 * K] + s2 * (1.0 - pk2 * pk2);
        const auto prev = filt.row(static_cast<Index>(i - 2 * K));
        for (int j = 0; j < p; ++j) {
          z[j] = sv[j] - pk2 * prev[j];
          dz[j] = terms[static_cast<std::size_t>(j)].d_dy(R.x[i], R.v[i]);
        }
        const double T = sv[p] - pk2 * prev[p];
        const std::size_t bl = r * per + std::min(per - 1, i * per / n);
        bG[bl].noalias() += z * z.transpose();
        bb[bl] += z * T - (0.5 * a22i + 2.0 * h * Ppred) * dz;
      }
    }
    for (std::size_t b = 0; b < nb; ++b) G += bG[b], bvec += bb[b];
    const Eigen::LDLT<MatrixXd> ldg(G);
    const VectorXd cn = ldg.solve(bvec);
    MatrixXd Om = MatrixXd::Zero(p, p);
    for (std::size_t b = 0; b < nb; ++b) {
      const VectorXd sc = bb[b] - bG[b] * cn;
      Om.noalias() += sc * sc.transpose();
    }
    const MatrixXd Gi = ldg.solve(MatrixXd::Identity(p, p));
    Jcov = Gi * Om * Gi.transpose();
    {
      std::vector<std::vector<double>> rn;
      residuals(cn, rn);
      fit_diffusion(rn, fo);
    }
    const double change = (cn - c).norm() / std::max(c.norm(), 1e-300);
    c = cn;
    if (round > 0 && std::abs(fo.tau - tau_prev) < 1e-3 * fo.tau && change < 1e-3) break;
  }
  // final residuals and autocovariance with the final drift; jackknife over batches for (τ, I)
  residuals(c, res);
  const int Lmax = std::min(Lcap, std::max(L1 + 1, 4 * L0));
  autocov(res, Lmax, S, N);
  {
    const VectorXd Cv = S.rowwise().sum().cwiseQuotient(N.rowwise().sum());
    std::vector<double> C(Cv.data(), Cv.data() + Cv.size());
    fo = fit_exponential(C, L0, L1, dt, h, given);
    require(fo.ok, "identify: colored_noise: the exponential fit of the residual autocovariance failed");
  }
  std::vector<double> jt, ji;
  const VectorXd St = S.rowwise().sum(), Nt = N.rowwise().sum();
  for (std::size_t b = 0; b < nb; ++b) {
    const VectorXd Cv = (St - S.col(static_cast<Index>(b))).cwiseQuotient(Nt - N.col(static_cast<Index>(b)));
    std::vector<double> C(Cv.data(), Cv.data() + Cv.size());
    const ColoredFitOut f = fit_exponential(C, L0, L1, dt, h, given);
    jt.push_back(f.tau);
    ji.push_back(f.intensity);
  }
  auto jack_sd = [&](const std::vector<double>& v) {
    double mean = 0;
    for (double t : v) mean += t;
    mean /= static_cast<double>(v.size());
    double ss = 0;
    for (double t : v) ss += (t - mean) * (t - mean);
    return std::sqrt(ss * (static_cast<double>(v.size()) - 1.0) / static_cast<double>(v.size()));
  };
  fit_diffusion(res, fo);

  Result out = std::move(cur);
  out.model.drift_stderr.clear();
  for (int j = 0; j < p; ++j) {
    out.model.drift[static_cast<std::size_t>(j)].coef = c[j];
    out.model.drift_stderr[terms[static_cast<std::size_t>(j)].name()] = std::sqrt(std::max(Jcov(j, j), 0.0));
  }
  out.model.diffusion_stderr.clear();
  for (int j = 0; j < q; ++j) {
    out.model.diffusion[static_cast<std::size_t>(j)].coef = qc[j];
    out.model.diffusion_stderr[dterms[static_cast<std::size_t>(j)].name()] = qse[j];
  }
  Effect fitted;
  fitted.id = EffectId::ColoredNoise;
  fitted.params = {{"tau", fo.tau}, {"intensity", fo.intensity}};
  if (!given.params.count("tau")) fitted.stderr_["tau"] = jack_sd(jt);
  if (!given.params.count("intensity")) fitted.stderr_["intensity"] = jack_sd(ji);
  out.model.effects = {fitted};
  info["rounds"] = rounds;
  info["lags_fitted_s"] = {L0 * dt, L1 * dt};
  info["eta_variance_in_residual"] = var_eta;
  info["residual_variance"] = St[0] / Nt[0];
  info["method"] =
      "colored_noise: tau and intensity from an exponential least-squares fit of the drift-residual "
      "autocovariance at lags >= 2 strides (tent kernels not overlapping); drift refitted by "
      "instrumental variables on the quasi-differenced equation (lag ~tau, instruments the "
      "dictionary two strides before the quasi-difference), iterated; white diffusion from the "
      "residual second moment minus the tent-averaged OU variance; standard errors: jackknife over "
      "contiguous batches (tau, intensity; drift held at its estimate), IV sandwich with batch sums "
      "(drift), batch sandwich (diffusion)";
  out.model.extra["dynamic_fit"] = info;
  append_effect_params(out.model, {fitted});
  return out;
}

}  // namespace detail

}  // namespace vehs::identify
