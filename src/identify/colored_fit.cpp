// identify with colored_noise (an Ornstein–Uhlenbeck excitation η, vehs/identify/dynamic.hpp):
// rounds of (the exponential fit of the drift-residual autocovariance at lags ≥ 2k → τ,
// intensity; the drift by GLS on the prediction errors of a Kalman filter of η; the white
// diffusion from the residual variance minus the OU part), then jackknife standard errors of τ
// and the intensity over contiguous batches.
#include "colored_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "block_covariance.hpp"
#include "term_fit.hpp"
#include "vehs/core/detail/format.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/dynamic.hpp"

namespace vehs::identify::detail {

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

std::string fmt(double v) { return vehs::detail::format_number(v, 5); }

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

/// The rows of every record (central kinematics at stride k), the baseline terms and the
/// batches (contiguous segments of records, at least 20 in all) of a colored_noise fit.
struct ColoredProblem {
  int k = 1;
  std::size_t K = 1;
  double dt = 0.0, h = 0.0;
  std::vector<Term> terms, dterms;  ///< drift and diffusion terms (the baseline's support)
  int p = 0, q = 0;
  std::vector<ColoredRows> rows;
  std::size_t per = 1, nb = 1;      ///< batches per record, batches in all

  ColoredProblem(const Dataset& data, const Options& options, const Model& baseline) {
    k = baseline.fit->stride;
    K = static_cast<std::size_t>(k);
    dt = data.common_dt();
    h = k * dt;
    terms = terms_of(baseline.drift);
    p = static_cast<int>(terms.size());
    require(p > 0, "identify: colored_noise needs at least one drift term");
    dterms = terms_of(baseline.diffusion);
    q = static_cast<int>(dterms.size());
    rows.resize(data.records.size());
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
    const std::size_t nrec = rows.size();
    per = nrec >= 20 ? 1 : (20 + nrec - 1) / nrec;
    nb = nrec * per;
  }

  /// Rows of batch bl: record, first and end row.
  void batch(std::size_t bl, std::size_t& r, std::size_t& b0, std::size_t& b1) const {
    r = bl / per;
    const std::size_t pp = bl % per, n = rows[r].a.size();
    b0 = n * pp / per;
    b1 = n * (pp + 1) / per;
  }

  /// Drift residuals r = â − Σ c_j ζ_j per record.
  void residuals(const VectorXd& coef, std::vector<std::vector<double>>& res) const {
    res.resize(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const ColoredRows& R = rows[r];
      res[r].resize(R.a.size());
      for (std::size_t i = 0; i < R.a.size(); ++i) {
        double f = 0;
        for (int j = 0; j < p; ++j) f += coef[j] * terms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], R.u[i]);
        res[r][i] = R.a[i] - f;
      }
    }
  }

  /// Autocovariance sums per batch up to lag Lmax (pairs whose first index lies in the batch):
  /// S(L, b) and the pair counts N(L, b).
  void autocovariance(const std::vector<std::vector<double>>& res, int Lmax, MatrixXd& S, MatrixXd& N) const {
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
  }
};

std::vector<double> pooled_autocovariance(const MatrixXd& S, const MatrixXd& N) {
  const VectorXd Cv = S.rowwise().sum().cwiseQuotient(N.rowwise().sum());
  return std::vector<double>(Cv.data(), Cv.data() + Cv.size());
}

/// The white diffusion: E[r²] = σ²·Q + (2/3)·a22/h (Q: tent self-average of the OU correlation),
/// least squares of (3h/2)(r² − σ²Q) on the diffusion terms with a batch sandwich.
struct WhiteDiffusion {
  VectorXd coef, se;
  double var_eta = 0.0;  ///< σ²·Q, the OU part of E[r²]
};

void fit_white_diffusion(const ColoredProblem& cp, const std::vector<std::vector<double>>& res, const ColoredFitOut& f,
                         WhiteDiffusion& wd) {
  const int q = cp.q;
  wd.var_eta = f.intensity / (2.0 * f.tau) * tent_self_factor(cp.h, f.tau);
  if (q == 0) return;
  MatrixXd G = MatrixXd::Zero(q, q);
  VectorXd g = VectorXd::Zero(q);
  std::vector<VectorXd> sb(cp.nb, VectorXd::Zero(q));
  std::vector<MatrixXd> Gb(cp.nb, MatrixXd::Zero(q, q));
  for (std::size_t bl = 0; bl < cp.nb; ++bl) {
    std::size_t r, b0, b1;
    cp.batch(bl, r, b0, b1);
    const ColoredRows& R = cp.rows[r];
    VectorXd psi(q);
    for (std::size_t i = b0; i < b1; ++i) {
      for (int j = 0; j < q; ++j) psi[j] = cp.dterms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], 0.0);
      const double y = (res[r][i] * res[r][i] - wd.var_eta) * 1.5 * cp.h;
      Gb[bl].noalias() += psi * psi.transpose();
      sb[bl] += psi * y;
    }
    G += Gb[bl];
    g += sb[bl];
  }
  const Eigen::LDLT<MatrixXd> ld(G);
  wd.coef = ld.solve(g);
  MatrixXd Om = MatrixXd::Zero(q, q);
  for (std::size_t b = 0; b < cp.nb; ++b) {
    const VectorXd s = sb[b] - Gb[b] * wd.coef;
    Om.noalias() += s * s.transpose();
  }
  const MatrixXd Gi = ld.solve(MatrixXd::Identity(q, q));
  const MatrixXd cov = Gi * Om * Gi.transpose();
  for (int j = 0; j < q; ++j) wd.se[j] = std::sqrt(std::max(cov(j, j), 0.0));
}

/// The drift by GLS on prediction errors: T_i = â_i − η̂(â)_i, Z_i = ζ_i − η̂(ζ)_i, with η̂ the
/// Kalman predictor of the OU state from rows ≤ i − 2k (linear in the filtered series, gains from
/// a22 only), plus the usual Itô correction ½·a22·∂ζ/∂v of the ULI noise. Returns the
/// coefficients; their batch-sandwich covariance into `cov`.
VectorXd gls_drift(const ColoredProblem& cp, const ColoredFitOut& fo, const VectorXd& qc, MatrixXd& cov) {
  const int p = cp.p, q = cp.q;
  const std::size_t K = cp.K, nb = cp.nb, per = cp.per, nrec = cp.rows.size();
  const double dt = cp.dt, h = cp.h;
  const double s2 = fo.intensity / (2.0 * fo.tau);
  const double p1 = std::exp(-dt / fo.tau), q1 = s2 * (1.0 - p1 * p1), pk2 = std::exp(-2.0 * h / fo.tau);
  MatrixXd G = MatrixXd::Zero(p, p);
  VectorXd bvec = VectorXd::Zero(p);
  std::vector<MatrixXd> bG(nb, MatrixXd::Zero(p, p));
  std::vector<VectorXd> bb(nb, VectorXd::Zero(p));
#pragma omp parallel for schedule(dynamic, 1)
  for (long rl = 0; rl < static_cast<long>(nrec); ++rl) {
    const std::size_t r = static_cast<std::size_t>(rl);
    const ColoredRows& R = cp.rows[r];
    const std::size_t n = R.a.size();
    MatrixXd filt(n, p + 1);  // filtered state of each series (columns: ζ_1..ζ_p, â)
    std::vector<double> Pf(n, s2);  // filter error variance after row i
    VectorXd mstate = VectorXd::Zero(p + 1), sv(p + 1), z(p), dz(p);
    double P = s2;
    for (std::size_t i = 0; i < n; ++i) {
      double a22i = 0.0;
      for (int j = 0; j < q; ++j) a22i += qc[j] * cp.dterms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], 0.0);
      const double Rv = std::max(a22i, 1e-6 * qc.cwiseAbs().sum() + 1e-300) / dt;
      if (i > 0) {
        mstate *= p1;
        P = p1 * p1 * P + q1;
      }
      for (int j = 0; j < p; ++j) sv[j] = cp.terms[static_cast<std::size_t>(j)].value(R.x[i], R.v[i], R.u[i]);
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
        dz[j] = cp.terms[static_cast<std::size_t>(j)].d_dy(R.x[i], R.v[i]);
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
  cov = Gi * Om * Gi.transpose();
  return cn;
}

/// The lags [L0, L1] of the exponential fit: Lmax grows (doubling, up to Lcap) until the pooled
/// autocovariance falls below 5 % of C(L0) within it. Fills S, N up to Lmax.
int lag_window(const ColoredProblem& cp, const std::vector<std::vector<double>>& res, int L0, int Lcap, int Lmax,
               MatrixXd& S, MatrixXd& N) {
  int L1 = L0;
  for (;;) {
    cp.autocovariance(res, Lmax, S, N);
    const VectorXd C = S.rowwise().sum().cwiseQuotient(N.rowwise().sum());
    L1 = L0;
    while (L1 < Lmax && C[L1 + 1] > 0.05 * C[L0]) ++L1;
    if (L1 < Lmax || Lmax >= Lcap) break;
    Lmax = std::min(Lcap, 2 * Lmax);
  }
  return L1;
}

/// Delete-one-batch jackknife standard errors of τ and the intensity.
std::pair<double, double> jackknife(const MatrixXd& S, const MatrixXd& N, int L0, int L1, double dt, double h,
                                    const Effect& given) {
  std::vector<double> jt, ji;
  const VectorXd St = S.rowwise().sum(), Nt = N.rowwise().sum();
  for (Index b = 0; b < S.cols(); ++b) {
    const VectorXd Cv = (St - S.col(b)).cwiseQuotient(Nt - N.col(b));
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
  return {jack_sd(jt), jack_sd(ji)};
}

/// The colored_noise entry of the options (params it gives are held fixed) and the options of the
/// baseline term fit (the other effects, which must be term-like and free).
Effect split_colored(const Options& options, Options& base) {
  base = options;
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
    require(!is_dynamic(e.id), "identify: colored_noise cannot yet be combined with the dynamic effect '" + e.name() + "'");
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
  return given;
}



/// The model file's covariance after the colored-noise fit (block_covariance): the GLS drift's
/// batch sandwich; the white diffusion's and the jackknifed (τ, I) standard errors, which come
/// from separate fits, as uncorrelated blocks.
ParameterCovariance colored_covariance(const Model& m, const ColoredProblem& cp, const MatrixXd& Jcov) {
  CovarianceBlock drift{{}, Jcov, {}}, others;
  for (const auto& t : cp.terms) {
    drift.names.push_back("drift[" + t.name() + "]");
    drift.stderr_.push_back(m.drift_stderr.at(t.name()));
  }
  for (const auto& [name, se] : m.diffusion_stderr) others.names.push_back("diffusion[" + name + "]"), others.stderr_.push_back(se);
  for (const auto& e : m.effects)
    for (const auto& [name, se] : e.stderr_)
      others.names.push_back(std::string(effect_spec(e.id).name) + "." + name), others.stderr_.push_back(se);
  const Eigen::VectorXd se = Eigen::Map<const Eigen::VectorXd>(others.stderr_.data(), static_cast<Eigen::Index>(others.stderr_.size()));
  others.cov = se.cwiseAbs2().asDiagonal();
  return block_covariance({drift, others});
}

}  // namespace

Result identify_colored(const Dataset& data, const Options& options) {
  Options base;
  const Effect given = split_colored(options, base);
  Result cur = identify_terms(data, base);
  require(cur.model.fit->estimator == Estimator::Uli,
          "identify: colored_noise needs the uli estimator (clean, densely sampled displacement); the "
          "options chose '" + enum_to_string(kEstimatorNames, cur.model.fit->estimator) + "'");
  const ColoredProblem cp(data, options, cur.model);
  const int p = cp.p, q = cp.q, L0 = 2 * cp.k;
  const double dt = cp.dt, h = cp.h;
  std::size_t nmin = std::numeric_limits<std::size_t>::max();
  for (const auto& R : cp.rows) nmin = std::min(nmin, R.a.size());
  require(nmin > 40 * cp.K, "identify: colored_noise needs records of more than " + std::to_string(42 * cp.K) + " samples");
  const int Lcap = static_cast<int>(std::min<std::size_t>(nmin / 8, 20000));

  VectorXd c(p);
  for (int j = 0; j < p; ++j) c[j] = cur.model.drift[static_cast<std::size_t>(j)].coef;
  WhiteDiffusion wd;
  wd.coef = VectorXd(q);
  wd.se = VectorXd::Zero(q);
  for (int j = 0; j < q; ++j) wd.coef[j] = cur.model.diffusion[static_cast<std::size_t>(j)].coef;
  std::vector<std::vector<double>> res;
  ColoredFitOut fo;
  int L1 = L0;
  MatrixXd S, N, Jcov;
  ColoredFitReport info;
  for (int round = 0; round < 6; ++round) {
    cp.residuals(c, res);
    L1 = lag_window(cp, res, L0, Lcap, std::min(Lcap, std::max(4 * L0, fo.ok ? static_cast<int>(5.0 * fo.tau / dt) : 64)), S, N);
    const std::vector<double> C = pooled_autocovariance(S, N);
    require(C[static_cast<std::size_t>(L0)] > 0 && L1 >= L0 + 2,
            "identify: colored_noise: the drift residuals show no positive autocorrelation persisting "
            "beyond the white-noise lags (C(" + fmt(L0 * dt) + " s) = " + fmt(C[static_cast<std::size_t>(L0)]) +
                ", below 5 % of it within " + std::to_string(L1 - L0 + 1) + " lags): no coloured excitation to fit");
    const double tau_prev = fo.tau;
    fo = fit_exponential(C, L0, L1, dt, h, given);
    require(fo.ok, "identify: colored_noise: the exponential fit of the residual autocovariance failed");
    info.rounds.push_back({fo.tau, fo.intensity, L0, L1});
    const VectorXd cn = gls_drift(cp, fo, wd.coef, Jcov);
    {
      std::vector<std::vector<double>> rn;
      cp.residuals(cn, rn);
      fit_white_diffusion(cp, rn, fo, wd);
    }
    const double change = (cn - c).norm() / std::max(c.norm(), 1e-300);
    c = cn;
    if (round > 0 && std::abs(fo.tau - tau_prev) < 1e-3 * fo.tau && change < 1e-3) break;
  }
  // final residuals and autocovariance with the final drift; jackknife over batches for (τ, I)
  cp.residuals(c, res);
  cp.autocovariance(res, std::min(Lcap, std::max(L1 + 1, 4 * L0)), S, N);
  fo = fit_exponential(pooled_autocovariance(S, N), L0, L1, dt, h, given);
  require(fo.ok, "identify: colored_noise: the exponential fit of the residual autocovariance failed");
  const auto [tau_se, intensity_se] = jackknife(S, N, L0, L1, dt, h, given);
  fit_white_diffusion(cp, res, fo, wd);

  Result out = std::move(cur);
  out.model.drift_stderr.clear();
  for (int j = 0; j < p; ++j) {
    out.model.drift[static_cast<std::size_t>(j)].coef = c[j];
    out.model.drift_stderr[cp.terms[static_cast<std::size_t>(j)].name()] = std::sqrt(std::max(Jcov(j, j), 0.0));
  }
  out.model.diffusion_stderr.clear();
  for (int j = 0; j < q; ++j) {
    out.model.diffusion[static_cast<std::size_t>(j)].coef = wd.coef[j];
    out.model.diffusion_stderr[cp.dterms[static_cast<std::size_t>(j)].name()] = wd.se[j];
  }
  Effect fitted;
  fitted.id = EffectId::ColoredNoise;
  fitted.params = {{"tau", fo.tau}, {"intensity", fo.intensity}};
  if (!given.params.count("tau")) fitted.stderr_["tau"] = tau_se;
  if (!given.params.count("intensity")) fitted.stderr_["intensity"] = intensity_se;
  out.model.effects = {fitted};
  out.model.covariance = colored_covariance(out.model, cp, Jcov);
  const VectorXd St = S.rowwise().sum(), Nt = N.rowwise().sum();
  info.lag_lo_time = L0 * dt;
  info.lag_hi_time = L1 * dt;
  info.eta_variance_in_residual = wd.var_eta;
  info.residual_variance = St[0] / Nt[0];
  out.report.colored = std::move(info);
  out.report.effect_params.push_back(fitted);
  return out;
}

}  // namespace vehs::identify::detail
