#include "diffusion_pass.hpp"

#include <algorithm>
#include <cmath>

#include "lens_mask.hpp"

namespace vehs::identify::detail {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

void accumulate_moments(const std::vector<double>& r, std::size_t len, std::size_t avail,
                        const std::vector<int>& lags, int lr_window, ResidualMoments& m) {
  const double* rp = r.data();
  double r2 = 0.0, r4 = 0.0;
  for (std::size_t j = 0; j < len; ++j) {
    const double q = rp[j] * rp[j];
    r2 += q, r4 += q * q;
  }
  m.n += static_cast<double>(len);
  m.r2 += r2;
  m.r4 += r4;
  for (std::size_t l = 0; l < lags.size(); ++l) {
    const auto lag = static_cast<std::size_t>(lags[l]);
    const std::size_t cnt = avail > lag ? std::min(len, avail - lag) : 0;
    double s = 0.0;
    for (std::size_t j = 0; j < cnt; ++j) s += rp[j] * rp[j + lag];
    m.lag_sum[l] += s;
    m.lag_n[l] += static_cast<double>(cnt);
  }
  if (lr_window > 0) {
    // Σ_j r_j (P[j + L + 1] − P[j + 1]) with prefix sums P, windows clipped at `avail`
    std::vector<double> P(avail + 1, 0.0);
    for (std::size_t j = 0; j < avail; ++j) P[j + 1] = P[j] + r[j];
    for (std::size_t j = 0; j < len; ++j) {
      const std::size_t hi = std::min(avail, j + 1 + static_cast<std::size_t>(lr_window));
      m.lr_sum += r[j] * (P[hi] - P[j + 1]);
    }
  }
}

namespace {

std::size_t extra_rows(const Kinematics& kin, const std::vector<int>& lags) {
  int e = kin.k;
  for (int l : lags) e = std::max(e, l);
  return static_cast<std::size_t>(e);
}

void diffusion_pass_span(const Context& cx, const DiffusionSetup& ds, const Span& sp,
                         DiffusionStats& acc) {
  const Record& rec = cx.data.records[sp.record];
  const std::size_t R = cx.kin.rows(rec.size);
  const std::size_t avail = std::min(R, sp.end + extra_rows(cx.kin, ds.lags)) - sp.begin;
  const std::size_t len = sp.end - sp.begin;
  thread_local std::vector<double> r, raw;  // reused between spans (no page faults)
  span_residuals(cx, ds.dm, rec, sp.begin, avail, r, ds.target == Target::RawKM ? &raw : nullptr);
  accumulate_moments(r, len, avail, ds.lags, 0, acc.mom);
  const double* x = cx.data.x_of(rec);
  const double* u = cx.data.u_of(rec);
  const int P = cx.psi.size();
  const Dictionary& phiS = ds.dm.phiS;
  const int pS = phiS.size();
  const auto& vt = phiS.velocity_terms();
  const int Kv = static_cast<int>(vt.size());
  const bool ito = ds.scores && ds.ito && Kv > 0;
  const bool noise = ds.scores && ds.noise;
  const double inv2h2 = 1.0 / (2.0 * cx.kin.h * cx.kin.h), two_h2 = 2.0 / (cx.kin.h * cx.kin.h);
  VectorXd cv(std::max(Kv, 1));
  for (int i = 0; i < Kv; ++i) cv[i] = ds.dm.cS[vt[static_cast<std::size_t>(i)]];

  RowBlock b;
  MatrixXd Psi(kB, P), Aw(kB, P + 1), Phi(kB, std::max(pS, 1)), Dv(kB, std::max(Kv, 1)),
      D2(kB, std::max(Kv, 1)), Dx(kB, std::max(pS, 1)), Gsub(P + 1, P + 1);
  VectorXd rr(kB), sw(kB), a22(kB), F(kB), dvc(kB), d2c(kB);
  std::vector<double> scratch(std::max(cx.psi.scratch_size(), phiS.scratch_size()));
  // batch accumulators
  const int RS = score_rows(ds, P), CS = score_cols(P);
  VectorXd bd = VectorXd::Zero(std::max(pS, 1)), be = VectorXd::Zero(std::max(pS, 1));
  MatrixXd bW = MatrixXd::Zero(std::max(Kv, 1), P), bG = MatrixXd::Zero(P + 1, P + 1);
  MatrixXd A(RS, CS);
  const std::size_t brows = static_cast<std::size_t>(ds.block_rows);
  const std::size_t nbatches = std::max<std::size_t>(1, len / brows);
  std::size_t batch = 1;
  auto batch_end = [&](std::size_t t) {
    // batch boundaries on multiples of the feature block, the last one at `len`
    if (t >= nbatches) return len;
    const std::size_t e = (len * t / nbatches) / kBlockRows * kBlockRows;
    return std::max<std::size_t>(e, kBlockRows);
  };
  std::size_t next_end = batch_end(batch);
  auto flush = [&] {
    A.setZero();
    A.col(0).head(pS) = bd.head(pS);
    A.col(0).tail(P) = bG.row(P).head(P).transpose();  // bG holds its lower triangle
    for (int j = 0; j < Kv; ++j) A.row(vt[static_cast<std::size_t>(j)]).segment(1, P) = -0.5 * bW.row(j);
    A.block(pS, 1, P, P) = -MatrixXd(bG.topLeftCorner(P, P).selfadjointView<Eigen::Lower>());
    A.col(P + 1).head(pS) = be.head(pS);
    const Eigen::Map<const VectorXd> va(A.data(), A.size());
    acc.kron.selfadjointView<Eigen::Lower>().rankUpdate(va);
    acc.batches += 1.0;
    bd.setZero();
    be.setZero();
    bW.setZero();
    bG.setZero();
  };
  thread_local std::vector<char> keep;
  if (cx.lens) lens_keep(cx, *cx.lens, rec, sp.begin, len, keep);
  int row[kBlockRows];  // block row of each (kept) row
  for (int c = 0; c < kBlockRows; ++c) row[c] = c;
  for (std::size_t j0 = 0; j0 < len; j0 += kBlockRows) {
    const int rows = static_cast<int>(std::min<std::size_t>(kBlockRows, len - j0));
    cx.load(x, u, sp.begin + j0, rows, b);
    acc.mom.v2 += Eigen::Map<const VectorXd>(b.v, rows).squaredNorm();
    const int m = cx.lens ? compact_rows(b, keep.data() + j0, row) : rows;
    cx.psi.values(b, Psi.data(), kB, scratch.data());
    if (ds.w.weighted) a22.head(m).noalias() = Psi.topLeftCorner(m, P) * ds.w.q;
    const bool need_dv = Kv > 0 && (ito || noise);
    if (pS > 0 && (ds.scores || need_dv)) phiS.values(b, Phi.data(), kB, scratch.data());
    if (need_dv) {
      phiS.d_dv(b, Dv.data(), kB, scratch.data());
      dvc.head(m).noalias() = Dv.topLeftCorner(m, Kv) * cv.head(Kv);  // ∂_v F
    }
    for (int c = 0; c < m; ++c) {
      const std::size_t j = j0 + static_cast<std::size_t>(row[c]);
      rr[c] = r[j];
      double z = 0.0, w = 1.0;
      if (!diffusion_target(ds.target, cx.kin, r, raw, j, avail, z, ds.uli_noise)) {
        w = 0.0;
      } else {
        acc.n += 1.0;
        acc.zsum += z;
        if (ds.w.weighted) w = 1.0 / std::max(a22[c], ds.w.floor);
      }
      sw[c] = w;
      Aw(c, P) = w * z;
    }
    for (int q = 0; q < P; ++q) Aw.col(q).head(m) = Psi.col(q).head(m).cwiseProduct(sw.head(m));
    Gsub.setZero();
    add_AtB(Aw, Aw, m, P + 1, P + 1, Gsub, true);
    acc.Gaug += Gsub;  // (only the lower triangle is meaningful)
    if (ds.scores) {
      bG += Gsub;
      if (pS > 0) {
        detail::add_AtB(Phi.data(), kB, rr.data(), kB, m, pS, 1, bd.data(), pS, false);
        if (ito) add_AtB(Dv, Psi, m, Kv, P, bW);
        if (noise) {
          // per unit s²: (1/2h²)[∂_vφ (∂_vφᵀc) + ½(φ ∂²_vφᵀc + ∂²_vφ φᵀc)] + (2/h²) ∂_xφ
          if (Kv > 0) {
            phiS.d2_dv2(b, D2.data(), kB, scratch.data());
            F.head(m).noalias() = Phi.topLeftCorner(m, pS) * ds.dm.cS;
            d2c.head(m).noalias() = D2.topLeftCorner(m, Kv) * cv.head(Kv);
            be.head(pS).noalias() += 0.5 * inv2h2 * (Phi.topLeftCorner(m, pS).transpose() * d2c.head(m));
            for (int jv = 0; jv < Kv; ++jv)
              be[vt[static_cast<std::size_t>(jv)]] +=
                  inv2h2 * (Dv.col(jv).head(m).dot(dvc.head(m)) + 0.5 * D2.col(jv).head(m).dot(F.head(m)));
          }
          phiS.d_dx(b, Dx.data(), kB, scratch.data());
          be.head(pS).noalias() += two_h2 * Dx.topLeftCorner(m, pS).colwise().sum().transpose();
        }
      }
      if (j0 + static_cast<std::size_t>(rows) >= next_end) {
        flush();
        ++batch;
        next_end = batch_end(batch);
      }
    }
  }
}

/// Moments of the residuals r[0, len) (lags into r[len, avail)) over the rows kept by `keep`.
void accumulate_kept(const std::vector<double>& r, const std::vector<char>& keep, std::size_t len, std::size_t avail,
                     const std::vector<int>& lags, ResidualMoments& m) {
  for (std::size_t j = 0; j < len; ++j)
    if (keep[j]) m.n += 1.0, m.r2 += r[j] * r[j], m.r4 += r[j] * r[j] * r[j] * r[j];
  for (std::size_t l = 0; l < lags.size(); ++l) {
    const auto lag = static_cast<std::size_t>(lags[l]);
    for (std::size_t j = 0; j < len && j + lag < avail; ++j)
      if (keep[j] && keep[j + lag]) m.lag_sum[l] += r[j] * r[j + lag], m.lag_n[l] += 1.0;
  }
}

/// The rows of a span as standardized_moments reads them: residuals of ds.dm, weights
/// 1/max(a22, floor), the rows kept (lens_keep under ds.dm, when `mask`) and, on request, the
/// drift dictionary's values (column-major, ld = avail).
struct StandardizedRows {
  std::size_t len = 0, avail = 0;
  std::vector<double> r, weight, phi;
  std::vector<char> keep;
};

void standardized_rows(const Context& cx, const DiffusionSetup& ds, const DiffusionWeights& w, const Span& sp,
                       bool with_phi, bool mask, StandardizedRows& s) {
  const Record& rec = cx.data.records[sp.record];
  s.avail = std::min(cx.kin.rows(rec.size), sp.end + extra_rows(cx.kin, ds.lags)) - sp.begin;
  s.len = sp.end - sp.begin;
  span_residuals(cx, ds.dm, rec, sp.begin, s.avail, s.r, nullptr);
  s.weight.assign(s.avail, 0.0);
  const double* x = cx.data.x_of(rec);
  const double* u = cx.data.u_of(rec);
  const int P = cx.psi.size(), pS = ds.dm.phiS.size();
  if (with_phi) s.phi.assign(s.avail * static_cast<std::size_t>(pS), 0.0);
  RowBlock b;
  MatrixXd Psi(kB, P), Phi(kB, std::max(pS, 1));
  VectorXd a22(kB);
  std::vector<double> scratch(std::max(cx.psi.scratch_size(), ds.dm.phiS.scratch_size()));
  for (std::size_t j0 = 0; j0 < s.avail; j0 += kBlockRows) {
    const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, s.avail - j0));
    cx.load(x, u, sp.begin + j0, m, b);
    cx.psi.values(b, Psi.data(), kB, scratch.data());
    a22.head(m).noalias() = Psi.topLeftCorner(m, P) * w.q;
    if (pS > 0 && with_phi) {
      ds.dm.phiS.values(b, Phi.data(), kB, scratch.data());
      for (int q = 0; q < pS; ++q)
        for (int c = 0; c < m; ++c) s.phi[static_cast<std::size_t>(q) * s.avail + j0 + static_cast<std::size_t>(c)] = Phi(c, q);
    }
    for (int c = 0; c < m; ++c) s.weight[j0 + static_cast<std::size_t>(c)] = 1.0 / std::max(a22[c], w.floor);
  }
  if (mask)
    lens_keep(cx, ds.dm, rec, sp.begin, s.avail, s.keep);
  else
    s.keep.assign(s.avail, 1);
}

/// Σ w φφᵀ and Σ w φ r over the kept rows of a span (the weighted refit of the drift).
struct KeptGram {
  MatrixXd G;
  VectorXd g;
  double kept = 0.0, rows = 0.0;
  explicit KeptGram(int p = 0) : G(MatrixXd::Zero(p, p)), g(VectorXd::Zero(p)) {}
};

KeptGram kept_gram(const Context& cx, const DiffusionSetup& ds, const DiffusionWeights& w, const std::vector<Span>& spans,
                   bool mask) {
  const int pS = ds.dm.phiS.size();
  KeptGram total(pS);
  run_spans<KeptGram>(
      spans, [&] { return KeptGram(pS); },
      [&](const Span& sp, KeptGram& acc) {
        thread_local StandardizedRows s;
        standardized_rows(cx, ds, w, sp, true, mask, s);
        acc.rows += static_cast<double>(s.len);
        for (std::size_t j = 0; j < s.len; ++j) {
          if (!s.keep[j]) continue;
          const Eigen::Map<const VectorXd, 0, Eigen::InnerStride<>> f(s.phi.data() + j, pS, Eigen::InnerStride<>(long(s.avail)));
          acc.G.noalias() += s.weight[j] * f * f.transpose();
          acc.g.noalias() += s.weight[j] * s.r[j] * f;
          acc.kept += 1.0;
        }
      },
      [&](const Span&, const KeptGram& acc) { total.G += acc.G, total.g += acc.g, total.kept += acc.kept, total.rows += acc.rows; },
      nullptr);
  return total;
}

}  // namespace

ResidualMoments standardized_moments(const Context& cx, const DiffusionSetup& ds, const DiffusionWeights& w,
                                     const std::vector<Span>& spans) {
  // the stiffness mask is for excursions beyond the lens's reach: where it would leave out half of
  // the rows or more (coarse sampling, a large stride) the data are read as they are (5 % was too
  // few: 2 of 60 noise-free pentastable y² seeds then read as noisy)
  bool mask = true;
  KeptGram total = kept_gram(cx, ds, w, spans, mask);
  if (!mask_holds(total.kept, total.rows)) total = kept_gram(cx, ds, w, spans, mask = false);
  const int pS = ds.dm.phiS.size();
  DiffusionSetup refit = ds;
  if (pS > 0) refit.dm.cS += total.G.ldlt().solve(total.g);
  ResidualMoments out(ds.lags.size());
  run_spans<ResidualMoments>(
      spans, [&] { return ResidualMoments(ds.lags.size()); },
      [&](const Span& sp, ResidualMoments& acc) {
        thread_local StandardizedRows s;
        standardized_rows(cx, refit, w, sp, false, mask, s);
        for (std::size_t j = 0; j < s.avail; ++j) s.r[j] *= std::sqrt(s.weight[j]);
        for (std::size_t j = 0; j < s.len; ++j)
          if (s.keep[j]) acc.wsum += s.weight[j];
        accumulate_kept(s.r, s.keep, s.len, s.avail, ds.lags, acc);
      },
      [&](const Span&, const ResidualMoments& acc) { out.add(acc); }, nullptr);
  return out;
}

std::vector<DiffusionStats> diffusion_pass(const Context& cx, const DiffusionSetup& ds,
                                           const std::vector<Span>& spans, int folds,
                                           vehs::detail::ProgressCounter* progress) {
  const int P = cx.psi.size();
  const int kd = ds.scores ? score_rows(ds, P) * score_cols(P) : 0;
  std::vector<DiffusionStats> out(static_cast<std::size_t>(folds), DiffusionStats(P, ds.lags.size(), kd));
  run_spans<DiffusionStats>(
      spans, [&] { return DiffusionStats(P, ds.lags.size(), kd); },
      [&](const Span& sp, DiffusionStats& acc) { diffusion_pass_span(cx, ds, sp, acc); },
      [&](const Span& sp, const DiffusionStats& acc) { out[static_cast<std::size_t>(sp.fold)].add(acc); },
      progress);
  for (auto& s : out) {
    s.Gaug.triangularView<Eigen::StrictlyUpper>() = s.Gaug.transpose();
    s.kron.triangularView<Eigen::StrictlyUpper>() = s.kron.transpose();
  }
  return out;
}

}  // namespace vehs::identify::detail
