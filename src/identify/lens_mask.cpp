#include "lens_mask.hpp"

#include <algorithm>
#include <cmath>

namespace vehs::identify::detail {

void lens_keep(const Context& cx, const DriftModel& dm, const Record& rec, std::size_t first, std::size_t count,
               std::vector<char>& keep) {
  const auto k = static_cast<std::size_t>(cx.kin.k);
  const std::size_t lo = first >= k ? first - k : 0;
  const std::size_t hi = std::min(cx.kin.rows(rec.size), first + count + k);
  const int pS = dm.phiS.size();
  thread_local std::vector<double> wh;  // ω·h of rows [lo, hi)
  wh.assign(hi - lo, 0.0);
  if (pS > 0) {
    RowBlock b;
    Eigen::MatrixXd Dx(kB, pS);
    Eigen::VectorXd bx(kB);
    double x0[kBlockRows];
    std::vector<double> scratch(dm.phiS.scratch_size());
    for (std::size_t j0 = lo; j0 < hi; j0 += kBlockRows) {
      const int m = static_cast<int>(std::min<std::size_t>(kBlockRows, hi - j0));
      cx.kin.load(cx.data.x_of(rec), cx.data.u_of(rec), j0, m, b);
      double* w = wh.data() + (j0 - lo);
      std::copy(b.x, b.x + m, x0);
      for (const double side : {0.0, 1.0, -1.0}) {
        for (int c = 0; c < m; ++c) b.x[c] = x0[c] + side * std::abs(b.v[c]) * cx.kin.h;
        dm.phiS.d_dx(b, Dx.data(), kB, scratch.data());
        bx.head(m).noalias() = Dx.topLeftCorner(m, pS) * dm.cS;
        for (int c = 0; c < m; ++c) w[c] = std::max(w[c], std::sqrt(std::abs(bx[c])) * cx.kin.h);
      }
    }
  }
  keep.assign(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = first + i - lo;  // row first + i in wh
    double w = wh[j];
    if (j >= k) w = std::max(w, wh[j - k]);
    if (j + k < wh.size()) w = std::max(w, wh[j + k]);
    keep[i] = w < kLensStiffnessLimit;
  }
}

int compact_rows(RowBlock& b, const char* keep, int* rows) {
  int n = 0;
  for (int c = 0; c < b.m; ++c) {
    if (!keep[c]) continue;
    b.x[n] = b.x[c], b.v[n] = b.v[c], b.a[n] = b.a[c], b.u[n] = b.u[c];
    rows[n++] = c;
  }
  b.m = n;
  return n;
}

}  // namespace vehs::identify::detail
