// identify with dynamic forces: rounds of (profile search of θ on the baseline support, the
// joint fit with sandwich standard errors, the term fit on the target corrected by the fitted
// force) until the support and estimator settle.
#include "profile_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "block_covariance.hpp"
#include "profile_problem.hpp"
#include "profile_search.hpp"
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

struct FitOut {
  VectorXd z;        // (c, β) at θ̂
  MatrixXd cov;      // of (c, β, θ_free)
  double contrast = 0.0, rows = 0.0;
  std::vector<double> beyond;  // impact: samples beyond each gap
  std::vector<std::string> term_names;  // drift terms of the engine (first K of z)
  std::vector<Component> comps;         // at θ̂ (β filled): the meaning of z's and cov's columns
  std::vector<std::pair<int, int>> free_theta;  // (component, θ index) of cov's last columns
};

/// Rows per batch of the sandwich's score covariance for p parameters over n rows: long against
/// the residual correlation, ≥ 30 batches per parameter. The scores of the dynamic parameters are
/// correlated over the slow time scales of the motion (hidden-state memory 1/λ, well hopping):
/// batches as long as ~40 per parameter allow (at least 1024 rows), not just beyond the residual
/// correlation.
std::size_t sandwich_batch_rows(const Problem& P, double n, int p) {
  const std::size_t corr_len = P.central ? 3 * static_cast<std::size_t>(P.k) : 2;
  std::size_t L = std::max<std::size_t>({1024, 50 * corr_len, static_cast<std::size_t>(n / (40.0 * p))});
  if (n / static_cast<double>(L) < 30.0 * p) L = std::max<std::size_t>(10 * corr_len + 10, static_cast<std::size_t>(n / (30.0 * p)));
  return L;
}

using Thetas = std::vector<std::vector<double>>;
using FreeTheta = std::vector<std::pair<int, int>>;

/// g = ∂f/∂θ of record r's dynamic force Σ β·col + off, by central differences in each free θ.
MatrixXd force_gradient(const Problem& P, const Thetas& th, std::size_t r, const FreeTheta& free_th,
                        const VectorXd& beta) {
  const int T = static_cast<int>(free_th.size());
  MatrixXd g(static_cast<Index>(P.data.records[r].size), T);
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
      VectorXd fcur = o2 + c2 * beta;
      (sgn < 0 ? fm : fp) = fcur;
    }
    g.col(j) = (fp - fm) / (2.0 * d);
  }
  return g;
}

/// Record r's share of the sandwich: the Hessian J = Σ Z'Z of (c, β, θ_free) and the covariance
/// O of the scores (with the Itô correction −½ Σ a22 ∂_vφ) summed over batches of L rows.
void record_sandwich(Problem& P, const Thetas& th, std::size_t r, const FreeTheta& free_th, const VectorXd& z,
                     std::size_t L, MatrixXd& J, MatrixXd& O) {
  const int K = P.K(), C = P.C(), T = static_cast<int>(free_th.size()), p = K + C + T;
  const Record& rec = P.data.records[r];
  J = MatrixXd::Zero(p, p);
  O = MatrixXd::Zero(p, p);
  MatrixXd cols;
  VectorXd off;
  P.record_columns(th, r, cols, off);
  const MatrixXd g = force_gradient(P, th, r, free_th, z.segment(K, C));
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
      const VectorXd res = be.t.head(m) - be.Z.topRows(m) * z;
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

/// Samples beyond the fitted gaps (positive, negative) of an impact_stop component; empty without.
std::vector<double> samples_beyond_gaps(const Problem& P) {
  std::vector<double> beyond;
  for (const auto& c : P.comps)
    if (c.id == EffectId::ImpactStop) {
      double np = 0, nn = 0;
      for (const auto& rec : P.data.records) {
        const double* x = P.data.x_of(rec);
        for (std::size_t i = 0; i < rec.size; ++i) np += x[i] > c.theta[0], nn += x[i] < -c.theta[1];
      }
      beyond = {np, nn};
    }
  return beyond;
}

/// Coefficients at θ̂ and the sandwich covariance J⁻¹ O J⁻ᵀ of (c, β, θ_free).
FitOut finish_fit(Problem& P) {
  FitOut out;
  auto th = P.thetas();
  P.set_noise_cov(th);
  const Moments M = moments(P, th);
  out.contrast = profile_contrast(M, &out.z);
  require(std::isfinite(out.contrast),
          "dynamic effects: the regression is degenerate at the fitted parameters (no signal of the effect)");
  out.rows = M.n;
  const int K = P.K();
  for (int j = 0; j < K; ++j) out.term_names.push_back(P.phi.name(j));
  int col = K;
  for (auto& c : P.comps) {
    c.beta = out.z.segment(col, c.ncols());
    col += c.ncols();
  }
  const FreeTheta free_th = P.free_theta();
  const int p = K + P.C() + static_cast<int>(free_th.size());
  const std::size_t L = sandwich_batch_rows(P, M.n, p);
  const std::size_t R = P.data.records.size();
  std::vector<MatrixXd> Jr(R), Om(R);
#pragma omp parallel for schedule(dynamic, 1)
  for (long rl = 0; rl < static_cast<long>(R); ++rl) {
    const std::size_t r = static_cast<std::size_t>(rl);
    record_sandwich(P, th, r, free_th, out.z, L, Jr[r], Om[r]);
  }
  MatrixXd J = MatrixXd::Zero(p, p), O = MatrixXd::Zero(p, p);
  for (std::size_t r = 0; r < R; ++r) J += Jr[r], O += Om[r];
  const MatrixXd Ji = J.fullPivLu().inverse();
  out.cov = Ji * O * Ji.transpose();
  out.beyond = samples_beyond_gaps(P);
  out.comps = P.comps;
  out.free_theta = free_th;
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

/// The options without the dynamic effects (their baseline), and the dynamic effects.
std::pair<Options, std::vector<Effect>> split_dynamic(const Options& options) {
  Options base = options;
  base.effects.clear();
  std::vector<Effect> dyn;
  for (const auto& e : options.effects) {
    if (!is_dynamic(e.id)) {
      base.effects.push_back(e);
      continue;
    }
    for (const auto& d : dyn) require(d.id != e.id, "effect '" + e.name() + "' is listed twice");
    dyn.push_back(e);
  }
  return {base, dyn};
}

/// The full drift library with the terms of the term-like effects.
std::vector<Term> full_drift_library(const Options& base) {
  std::vector<Term> full = base.drift_library;
  for (const auto& e : base.effects)
    for (const auto& tc : unit_effect_terms(e.id).drift)
      if (std::find(full.begin(), full.end(), tc.term) == full.end()) full.push_back(tc.term);
  return full;
}

/// The profile problem of a round: the kinematics of the current term fit, the drift terms
/// `support`, its diffusion, the sign kernel's width from the velocity's spread, the baseline
/// moments without the dynamic effects.
void set_up_round(Problem& P, const Model& cur, const std::vector<Term>& support, std::vector<Component> comps) {
  const Dataset& data = P.data;
  const FitInfo& fit = *cur.fit;
  P.central = uses_central_kinematics(fit.estimator);
  P.k = P.central ? fit.stride : 1;
  P.dt = data.common_dt();
  P.h = P.central ? P.k * P.dt : P.dt;
  P.lead = P.central ? static_cast<std::size_t>(P.k) : 0;
  P.trail = P.central ? static_cast<std::size_t>(P.k) : 2;
  P.phi = Dictionary(support);
  P.psi = Dictionary(terms_of(cur.diffusion));
  P.q = VectorXd(P.psi.size());
  for (int j = 0; j < P.psi.size(); ++j) P.q[j] = cur.diffusion[static_cast<std::size_t>(j)].coef;
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
  if (P.central) P.phi.set_sign_smoothing(P.h, cur.diffusion, 1e-300, 0.0);
  P.comps = std::move(comps);
  P.base = std::make_shared<const BaseMoments>(base_moments(P));
  P.c_base = P.base->G.ldlt().solve(P.base->b);  // baseline drift without the dynamic effects
}

/// The fitted effects' force per sample (aligned with Dataset::x).
void fill_dynamic_force(const std::vector<Effect>& fitted, const Dataset& data, const Problem& P,
                        std::vector<double>& force) {
  for (const auto& rec : data.records) {
    std::vector<double> f;
    dynamic_force(fitted, data, rec, f, P.central ? P.k : 0);
    std::copy(f.begin(), f.end(), force.begin() + static_cast<long>(rec.offset));
  }
}

/// Drift-term standard errors: the larger of identify's (conditional on the dynamic force, with
/// the diffusion coupling of the Itô correction) and the joint one of the profile fit (which
/// carries the uncertainty of the effect's parameters — e.g. damping vs electromechanical
/// coupling are strongly correlated).
void use_joint_stderr(const FitOut& fit, Model& m) {
  for (std::size_t j = 0; j < fit.term_names.size(); ++j) {
    auto it = m.drift_stderr.find(fit.term_names[j]);
    if (it == m.drift_stderr.end()) continue;
    const double joint = sd(fit.cov, static_cast<int>(j));
    if (std::isfinite(joint)) it->second = std::max(it->second, joint);
  }
}

/// The model file's covariance after a profile fit (block_covariance): the fit's sandwich over
/// the drift terms and the effects' parameters as written (harmonic forcing's amplitude and phase
/// by the delta method), with the written standard errors (use_joint_stderr's); then the final
/// term fit's block of the diffusion terms (and of any drift term the profile fit did not have).
ParameterCovariance profile_covariance(const FitOut& f, const Model& m, const ParameterCovariance& term_cov) {
  const Eigen::Index p = f.cov.rows();
  CovarianceBlock joint;
  std::vector<Eigen::RowVectorXd> rows;
  auto add = [&](const std::string& name, double se, Eigen::RowVectorXd g) {
    joint.names.push_back(name);
    joint.stderr_.push_back(se);
    rows.push_back(std::move(g));
  };
  auto unit = [&](Eigen::Index i) { return Eigen::RowVectorXd::Unit(p, i); };
  const int K = static_cast<int>(f.term_names.size());
  for (int j = 0; j < K; ++j)
    if (auto it = m.drift_stderr.find(f.term_names[static_cast<std::size_t>(j)]); it != m.drift_stderr.end())
      add("drift[" + it->first + "]", it->second, unit(j));
  int col = K, C = 0;
  for (const auto& c : f.comps) C += c.ncols();
  for (std::size_t ci = 0; ci < f.comps.size() && ci < m.effects.size(); ++ci) {
    const Component& c = f.comps[ci];
    const Effect& e = m.effects[ci];
    const std::string prefix = std::string(effect_spec(c.id).name) + ".";
    auto se = [&](const std::string& param) {
      auto it = e.stderr_.find(param);
      return it == e.stderr_.end() ? -1.0 : it->second;
    };
    if (c.id == EffectId::HarmonicForcing && c.ncols() == 2) {
      const double A = c.beta[0], B = c.beta[1], R = std::hypot(A, B);
      Eigen::RowVectorXd gR = Eigen::RowVectorXd::Zero(p), gP = Eigen::RowVectorXd::Zero(p);
      gR[col] = A / R, gR[col + 1] = B / R;
      gP[col] = B / (R * R), gP[col + 1] = -A / (R * R);
      add(prefix + "amplitude", se("amplitude"), gR);
      add(prefix + "phase", se("phase"), gP);
    } else {
      for (int j = 0; j < c.ncols(); ++j)
        add(prefix + c.beta_names[static_cast<std::size_t>(j)], se(c.beta_names[static_cast<std::size_t>(j)]), unit(col + j));
    }
    col += c.ncols();
    for (std::size_t j = 0; j < f.free_theta.size(); ++j)
      if (f.free_theta[j].first == static_cast<int>(ci)) {
        const std::string& name = c.theta_names[static_cast<std::size_t>(f.free_theta[j].second)];
        add(prefix + name, se(name), unit(K + C + static_cast<Eigen::Index>(j)));
      }
  }
  MatrixXd G(static_cast<Eigen::Index>(rows.size()), p);
  for (std::size_t i = 0; i < rows.size(); ++i) G.row(static_cast<Eigen::Index>(i)) = rows[i];
  joint.cov = G * f.cov * G.transpose();
  CovarianceBlock rest;  // the term fit's, for the names the profile fit has not
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < term_cov.size(); ++i) {
    const std::string& name = term_cov.names[i];
    if (std::find(joint.names.begin(), joint.names.end(), name) != joint.names.end()) continue;
    const bool drift = name.rfind("drift[", 0) == 0;
    const auto& written = drift ? m.drift_stderr : m.diffusion_stderr;
    const auto it = written.find(name.substr(drift ? 6 : 10, name.size() - (drift ? 7 : 11)));
    if (it == written.end()) continue;  // a term the final model does not have
    idx.push_back(i);
    rest.names.push_back(name);
    rest.stderr_.push_back(it->second);
  }
  rest.cov.resize(static_cast<Eigen::Index>(idx.size()), static_cast<Eigen::Index>(idx.size()));
  for (std::size_t a = 0; a < idx.size(); ++a)
    for (std::size_t b = 0; b < idx.size(); ++b)
      rest.cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = term_cov(idx[a], idx[b]);
  return block_covariance({joint, rest});
}

}  // namespace

Result identify_profile(const Dataset& data, const Options& options) {
  const auto [base, dyn] = split_dynamic(options);
  std::vector<Component> comps;
  for (const auto& e : dyn) comps.push_back(make_component(e));

  Result cur = identify_terms(data, base);
  ProfileFitReport info;
  std::vector<Effect> fitted;
  FitOut fit;
  std::vector<double> force(data.x.size(), 0.0);
  // the first profile fit runs on the full drift library, because a selection made without the
  // dynamic effect can have absorbed it (high powers of x standing in for the stops); later
  // rounds use identify's selection made with the fitted dynamic force subtracted
  const std::vector<Term> full = full_drift_library(base);
  for (int round = 0; round < 3; ++round) {
    Problem P(data);
    const FitInfo cur_fit = *cur.model.fit;
    const std::vector<Term> support = round == 0 ? full : terms_of(cur.model.drift);
    set_up_round(P, cur.model, support, comps);
    search_theta(P, info, round > 0);
    comps = P.comps;  // warm start of the next round
    fit = finish_fit(P);
    fitted = effects_of(P, fit);
    info.rounds.push_back({cur_fit.estimator, P.k, terms_of(cur.model.drift), fitted, fit.contrast});
    fill_dynamic_force(fitted, data, P, force);
    Options with_force = base;
    with_force.known_force = &force;
    cur = identify_terms(data, with_force);
    const bool same = terms_of(cur.model.drift) == support && cur.model.fit->estimator == cur_fit.estimator &&
                      cur.model.fit->stride == cur_fit.stride;
    if (same) break;
  }
  Result res = std::move(cur);
  res.model.effects = fitted;
  use_joint_stderr(fit, res.model);
  res.model.covariance = profile_covariance(fit, res.model, res.model.covariance);
  info.effects = fitted;
  info.profile_contrast = fit.contrast;
  info.rows = fit.rows;
  if (!fit.beyond.empty()) info.samples_beyond_gap = std::array<double, 2>{fit.beyond[0], fit.beyond[1]};
  res.report.profile = std::move(info);
  res.report.effect_params.insert(res.report.effect_params.end(), fitted.begin(), fitted.end());
  return res;
}

}  // namespace vehs::identify::detail
