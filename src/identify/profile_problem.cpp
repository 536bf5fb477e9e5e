#include "profile_problem.hpp"

#include <algorithm>
#include <cmath>

#include "vehs/effects/impact_stop.hpp"
#include "vehs/core/error.hpp"
#include "vehs/identify/dynamic.hpp"

namespace vehs::identify::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

Component make_component(const Effect& e) {
  Component c;
  c.id = e.id;
  c.given = e;
  auto nonlinear = [&](const char* name) {
    c.theta_names.emplace_back(name);
    c.theta_free.push_back(!has_param(e, name));
    c.theta.push_back(has_param(e, name) ? e.params.at(name) : 0.0);
  };
  switch (e.id) {
    case EffectId::HarmonicForcing:
      nonlinear("omega");
      if (has_param(e, "amplitude") && !has_param(e, "phase"))
        throw Error("effect 'harmonic_forcing': amplitude can only be held fixed together with phase");
      if (!has_param(e, "phase")) c.beta_names = {"A_cos", "B_sin"};
      else if (!has_param(e, "amplitude")) c.beta_names = {"amplitude"};
      break;
    case EffectId::ImpactStop:
      nonlinear("gap");
      nonlinear("gap_neg");
      if (!has_param(e, "k_stop")) c.beta_names = {"k_stop"};
      break;
    case EffectId::ElectromechanicalCoupling:
      nonlinear("lambda");
      if (!has_param(e, "coupling")) c.beta_names = {"coupling"};
      break;
    default:
      throw Error("effect '" + e.name() + "': identification of this dynamic effect is not supported yet");
  }
  c.beta = VectorXd::Zero(c.ncols());
  return c;
}

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
      effects::impact_stop_record_shape(x, n, theta[0], theta[1], tent_k, scratch.data());
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

std::vector<SpanRef> spans_of(const Problem& P, std::size_t r) {
  std::vector<SpanRef> s;
  const std::size_t n = P.data.records[r].size;
  if (n <= P.lead + P.trail) return s;
  const std::size_t b = P.lead, e = n - P.trail;
  for (std::size_t i = b; i < e; i += kProfileSpanRows) s.push_back({r, i, std::min(e, i + kProfileSpanRows)});
  return s;
}

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

double profile_contrast(const Moments& M, VectorXd* coef) {
  const Eigen::LDLT<MatrixXd> ldlt(M.G);
  if (ldlt.info() != Eigen::Success) return kProfileInf;
  // degenerate: a column without signal (e.g. no sample beyond a gap)
  const VectorXd d = ldlt.vectorD();
  if (d.minCoeff() <= 1e-12 * std::max(d.maxCoeff(), 1e-300)) return kProfileInf;
  const VectorXd z = ldlt.solve(M.b);
  if (coef) *coef = z;
  return M.aa - M.b.dot(z);
}

double contrast_at(const Problem& P, const std::vector<std::vector<double>>& th) {
  return profile_contrast(moments(P, th));
}

}  // namespace vehs::identify::detail
