#pragma once
// Gram accumulation C += Aᵀ·B for thin column-major blocks (m ≤ a few hundred rows, up to ~30
// columns): the shape of the feature blocks of identify's streaming passes (and of any
// least-squares problem accumulated block by block). Eigen's GEMM packs its operands, which
// costs more than the arithmetic at these sizes; this kernel keeps a 4×2 tile of C in registers
// and streams the rows (GCC/Clang vector extensions: AVX when available, SSE otherwise).
// Results are deterministic (fixed summation order), hence independent of how blocks are
// distributed over threads as long as they are reduced in a fixed order.
#include <cstddef>
#include <cstring>

#include <Eigen/Core>

// Without AVX (the portable build) GCC notes that 32-byte vectors would be passed differently
// across an ABI boundary; these helpers are inline and private, so no such boundary exists.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace vehs::identify {

namespace detail {  // the raw kernel and its vector helpers (add_gram below is the API)

typedef double v4d __attribute__((vector_size(32)));

inline v4d load4(const double* p) {
  v4d v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline double hsum(v4d v) { return (v[0] + v[1]) + (v[2] + v[3]); }

/// C(i, j) += Σ_r A(r, i)·B(r, j) for i < na, j < nb; `lower` restricts to i ≥ j (A == B).
/// Column-major: A(r, i) = A[r + i·lda].
inline void add_AtB(const double* A, std::ptrdiff_t lda, const double* B, std::ptrdiff_t ldb,
                    int m, int na, int nb, double* C, std::ptrdiff_t ldc, bool lower) {
  const int m4 = m & ~3;
  for (int j = 0; j < nb; j += 2) {
    const int jn = (j + 1 < nb) ? 2 : 1;
    const double* b0 = B + j * ldb;
    const double* b1 = B + (j + jn - 1) * ldb;
    for (int i = lower ? (j & ~3) : 0; i < na; i += 4) {
      const int in = na - i < 4 ? na - i : 4;
      const double* a[4];
      for (int t = 0; t < 4; ++t) a[t] = A + (i + (t < in ? t : in - 1)) * lda;
      v4d s00 = {0, 0, 0, 0}, s10 = s00, s20 = s00, s30 = s00;
      v4d s01 = s00, s11 = s00, s21 = s00, s31 = s00;
      for (int r = 0; r < m4; r += 4) {
        const v4d x0 = load4(b0 + r), x1 = load4(b1 + r);
        const v4d y0 = load4(a[0] + r), y1 = load4(a[1] + r), y2 = load4(a[2] + r), y3 = load4(a[3] + r);
        s00 += y0 * x0;
        s10 += y1 * x0;
        s20 += y2 * x0;
        s30 += y3 * x0;
        s01 += y0 * x1;
        s11 += y1 * x1;
        s21 += y2 * x1;
        s31 += y3 * x1;
      }
      double c0[4] = {hsum(s00), hsum(s10), hsum(s20), hsum(s30)};
      double c1[4] = {hsum(s01), hsum(s11), hsum(s21), hsum(s31)};
      for (int r = m4; r < m; ++r)
        for (int t = 0; t < 4; ++t) {
          c0[t] += a[t][r] * b0[r];
          c1[t] += a[t][r] * b1[r];
        }
      for (int t = 0; t < in; ++t) {
        const int row = i + t;
        if (!lower || row >= j) C[row + j * ldc] += c0[t];
        if (jn == 2 && (!lower || row >= j + 1)) C[row + (j + 1) * ldc] += c1[t];
      }
    }
  }
}

}  // namespace detail

/// C += Aᵀ·B over the first `rows` rows of A and B (column-major Eigen matrices); with `lower`
/// (A and B the same matrix) only the lower triangle of C is updated.
template <class DA, class DB, class DC>
void add_gram(const Eigen::DenseBase<DA>& A, const Eigen::DenseBase<DB>& B, int rows,
              Eigen::DenseBase<DC>& C, bool lower = false) {
  static_assert(!DA::IsRowMajor && !DB::IsRowMajor && !DC::IsRowMajor, "column-major blocks");
  detail::add_AtB(A.derived().data(), A.derived().outerStride(), B.derived().data(), B.derived().outerStride(), rows,
                static_cast<int>(A.cols()), static_cast<int>(B.cols()), C.derived().data(), C.derived().outerStride(),
                lower);
}

}  // namespace vehs::identify

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
