#pragma once
// Gram accumulation C += Aᵀ·B for thin column-major blocks (m ≤ a few hundred rows, up to ~30
// columns): the shape of the feature blocks of identify's streaming passes (and of any
// least-squares problem accumulated block by block). Eigen's GEMM packs its operands, which
// costs more than the arithmetic at these sizes; this kernel keeps a 4×2 tile of C in registers
// and streams the rows. It is compiled into the library once per instruction-set level (scalar,
// SSE2, AVX2, AVX-512: src/identify/simd/gram_kernel.inc) and runs at the level chosen by
// vehs/sim/simd.hpp (the widest the CPU has, or VEHS_SIMD), so a portable build gets the wide
// registers too. Results are deterministic (fixed summation order, bitwise the same at every
// level), hence independent of how blocks are distributed over threads as long as they are
// reduced in a fixed order.
#include <cstddef>

#include <Eigen/Core>

namespace vehs::identify {

namespace detail {  // the raw kernel (add_gram below is the API)

/// C(i, j) += Σ_r A(r, i)·B(r, j) for i < na, j < nb; `lower` restricts to i ≥ j (A == B).
/// Column-major: A(r, i) = A[r + i·lda].
void add_AtB(const double* A, std::ptrdiff_t lda, const double* B, std::ptrdiff_t ldb, int m, int na, int nb,
             double* C, std::ptrdiff_t ldc, bool lower);

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
