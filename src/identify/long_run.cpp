#include "long_run.hpp"

#include <algorithm>

namespace vehs::identify::detail {

using Eigen::MatrixXd;
using Eigen::VectorXd;

void long_run_span(const Context& cx, const DiffusionSetup& ds, const VectorXd& q, int lr_r,
                   int lr_e, const Span& sp, LongRun& acc) {
  const Record& rec = cx.data.records[sp.record];
  const std::size_t R = cx.kin.rows(rec.size);
  const std::size_t ext = static_cast<std::size_t>(std::max({lr_r, lr_e, cx.kin.k}));
  const std::size_t avail = std::min(R, sp.end + ext) - sp.begin;
  const std::size_t len = sp.end - sp.begin;
  std::vector<double> r, raw;
  span_residuals(cx, ds.dm, rec, sp.begin, avail, r, ds.target == Target::RawKM ? &raw : nullptr);
  std::vector<double> e(avail, 0.0);
  const double* x = cx.data.x_of(rec);
  const double* u = cx.data.u_of(rec);
  const int P = cx.psi.size();
  RowBlock b;
  MatrixXd Psi(kB, P);
  VectorXd a22(kB);
  std::vector<double> scratch(cx.psi.scratch_size());
  for (std::size_t j0 = 0; j0 < avail; j0 += kBlockRows) {
    const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, avail - j0));
    cx.load(x, u, sp.begin + j0, m, b);
    cx.psi.values(b, Psi.data(), kB, scratch.data());
    a22.head(m).noalias() = Psi.topLeftCorner(m, P) * q;
    for (int c = 0; c < m; ++c) {
      double z;
      if (diffusion_target(ds.target, cx.kin, r, raw, j0 + static_cast<std::size_t>(c), avail, z, ds.uli_noise))
        e[j0 + static_cast<std::size_t>(c)] = z - a22[c];
    }
  }
  auto window = [&](const std::vector<double>& v, int L, double& s2, double& slr) {
    std::vector<double> Pf(avail + 1, 0.0);
    for (std::size_t j = 0; j < avail; ++j) Pf[j + 1] = Pf[j] + v[j];
    for (std::size_t j = 0; j < len; ++j) {
      const std::size_t hi = std::min(avail, j + 1 + static_cast<std::size_t>(L));
      s2 += v[j] * v[j];
      slr += v[j] * (Pf[hi] - Pf[j + 1]);
    }
  };
  window(r, lr_r, acc.r2, acc.r_lr);
  window(e, lr_e, acc.e2, acc.e_lr);
}

}  // namespace vehs::identify::detail
