#include "drift_pass.hpp"

#include <algorithm>

#include "lens_mask.hpp"

namespace vehs::identify::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

void drift_pass_span(const Context& cx, bool ito, bool noise, const Span& sp, DriftStats& acc) {
  const Record& rec = cx.data.records[sp.record];
  const double* x = cx.data.x_of(rec);
  const double* u = cx.data.u_of(rec);
  const int K = cx.phi.size(), P = cx.psi.size();
  const int Kv = static_cast<int>(cx.phi.velocity_terms().size());
  ito = ito && Kv > 0;
  RowBlock b;
  MatrixXd Phi(kB, K + 1), Psi(kB, P), Dv(kB, std::max(Kv, 1)), D2(kB, std::max(Kv, 1)), Dx(kB, K);
  MatrixXd Resp(kB, std::max(Kv, 1));
  std::vector<double> scratch(std::max(cx.phi.scratch_size(), cx.psi.scratch_size()));
  thread_local std::vector<char> keep;
  if (cx.lens) lens_keep(cx, *cx.lens, rec, sp.begin, sp.end - sp.begin, keep);
  int kept_rows[kBlockRows];
  for (std::size_t j0 = sp.begin; j0 < sp.end; j0 += kBlockRows) {
    int m = static_cast<int>(std::min<std::size_t>(kBlockRows, sp.end - j0));
    cx.load(x, u, j0, m, b);
    double lo = acc.xmin, hi = acc.xmax, v2 = 0.0;
    for (int c = 0; c < m; ++c) {
      lo = std::min(lo, b.x[c]);
      hi = std::max(hi, b.x[c]);
      v2 += b.v[c] * b.v[c];
    }
    acc.xmin = lo;
    acc.xmax = hi;
    acc.v2 += v2;
    if (cx.lens) {  // the data's range and velocity scale above are over every row
      const int all = m;
      m = compact_rows(b, keep.data() + (j0 - sp.begin), kept_rows);
      acc.left_out += all - m;
    }
    cx.phi.values(b, Phi.data(), kB, scratch.data());
    for (int c = 0; c < m; ++c) Phi(c, K) = b.a[c];
    add_AtB(Phi, Phi, m, K + 1, K + 1, acc.Gaug, true);
    if (ito || (noise && Kv > 0)) cx.phi.d_dv(b, Dv.data(), kB, scratch.data());
    if (ito) {
      cx.psi.values(b, Psi.data(), kB, scratch.data());
      add_AtB(Psi, Dv, m, P, Kv, acc.ito);
      if (cx.phi.sign_smoothing()) {
        cx.phi.sign_ito_response(b, Resp.data(), kB);
        acc.resp.noalias() += Resp.topRows(m).colwise().sum().transpose();
      }
    }
    if (noise) {
      if (Kv > 0) {
        cx.phi.d2_dv2(b, D2.data(), kB, scratch.data());
        add_AtB(Dv, Dv, m, Kv, Kv, acc.hvv);
        add_AtB(Phi, D2, m, K, Kv, acc.h2);
      }
      cx.phi.d_dx(b, Dx.data(), kB, scratch.data());
      acc.dx.noalias() += Dx.topRows(m).colwise().sum().transpose();
    }
    acc.n += m;
  }
}

}  // namespace

std::vector<DriftStats> drift_pass(const Context& cx, bool ito, bool noise,
                                   const std::vector<Span>& spans, int folds, vehs::detail::ProgressCounter* progress) {
  const int K = cx.phi.size(), P = cx.psi.size();
  const int Kv = static_cast<int>(cx.phi.velocity_terms().size());
  std::vector<DriftStats> out(static_cast<std::size_t>(folds), DriftStats(K, P, Kv));
  run_spans<DriftStats>(
      spans, [&] { return DriftStats(K, P, Kv); },
      [&](const Span& sp, DriftStats& acc) { drift_pass_span(cx, ito, noise, sp, acc); },
      [&](const Span& sp, const DriftStats& acc) { out[static_cast<std::size_t>(sp.fold)].add(acc); },
      progress);
  for (auto& s : out) s.Gaug.triangularView<Eigen::StrictlyUpper>() = s.Gaug.transpose();
  return out;
}

QuadraticStats drift_quadratic(const DriftStats& s, const Dictionary& phi,
                               const DriftCorrection& corr) {
  const int K = phi.size();
  QuadraticStats q(K);
  q.G = s.Gaug.topLeftCorner(K, K);
  q.b = s.Gaug.col(K).head(K);
  q.c0 = s.Gaug(K, K);
  q.n = s.n;
  const auto& vt = phi.velocity_terms();
  if (corr.ito && !vt.empty() && corr.q.size() > 0) {
    const VectorXd c = s.ito.transpose() * corr.q;  // Σ ∂_vφ_j a22
    for (std::size_t i = 0; i < vt.size(); ++i) q.b[vt[i]] -= 0.5 * c[static_cast<Index>(i)];
    // the friction's response (smoothed_sign.hpp): −μ·Σ ½a22 S'Q = c·(…), on the diagonal
    for (std::size_t i = 0; i < vt.size(); ++i) q.G(vt[i], vt[i]) += s.resp[static_cast<Index>(i)];
  }
  if (corr.var_v_noise != 0.0 && !vt.empty()) {
    MatrixXd H = MatrixXd::Zero(K, K);
    for (std::size_t i = 0; i < vt.size(); ++i)
      for (std::size_t j = 0; j < vt.size(); ++j)
        H(vt[i], vt[j]) += s.hvv(static_cast<Index>(i), static_cast<Index>(j));
    MatrixXd H2 = MatrixXd::Zero(K, K);
    for (std::size_t j = 0; j < vt.size(); ++j) H2.col(vt[j]) = s.h2.col(static_cast<Index>(j));
    H += 0.5 * (H2 + H2.transpose());
    q.G -= corr.var_v_noise * H;
  }
  if (corr.ax_cov != 0.0) q.b += corr.ax_cov * s.dx;
  return q;
}

DriftModel drift_model(const Dictionary& phi, const std::vector<int>& S, const VectorXd& c) {
  DriftModel dm{phi.subset(S), VectorXd(static_cast<Index>(S.size()))};
  for (std::size_t i = 0; i < S.size(); ++i) dm.cS[static_cast<Index>(i)] = c[S[i]];
  return dm;
}

void span_residuals(const Context& cx, const DriftModel& dm, const Record& rec, std::size_t first,
                    std::size_t count, std::vector<double>& r, std::vector<double>* raw) {
  const double* x = cx.data.x_of(rec);
  const double* u = cx.data.u_of(rec);
  r.resize(count);
  if (raw) raw->resize(count);
  RowBlock b;
  const int pS = dm.phiS.size();
  MatrixXd Phi(kB, std::max(pS, 1));
  std::vector<double> scratch(dm.phiS.scratch_size());
  for (std::size_t j = 0; j < count; j += kBlockRows) {
    const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, count - j));
    cx.load(x, u, first + j, m, b);
    if (raw) std::copy(b.a, b.a + m, raw->data() + j);
    if (pS == 0) {
      std::copy(b.a, b.a + m, r.data() + j);
      continue;
    }
    dm.phiS.values(b, Phi.data(), kB, scratch.data());
    Eigen::Map<VectorXd> rr(r.data() + j, m);
    rr = Eigen::Map<const VectorXd>(b.a, m) - Phi.topLeftCorner(m, pS) * dm.cS;
  }
}

}  // namespace vehs::identify::detail
