// The Gram kernel's entry point (vehs/identify/gram.hpp): the copy compiled for the SIMD level in
// use (vehs/sim/simd.hpp: the widest the CPU has, or VEHS_SIMD), from
// src/identify/simd/gram_kernel.inc. Every level gives bitwise the same sums.
#include "vehs/identify/gram.hpp"

#include "vehs/sim/simd.hpp"

namespace vehs::identify {

#define VEHS_GRAM_LEVEL(level)                                                                          \
  namespace simd_##level {                                                                             \
  void add_AtB(const double* A, std::ptrdiff_t lda, const double* B, std::ptrdiff_t ldb, int m, int na, \
               int nb, double* C, std::ptrdiff_t ldc, bool lower);                                     \
  }
VEHS_GRAM_LEVEL(scalar)
VEHS_GRAM_LEVEL(sse2)
VEHS_GRAM_LEVEL(avx2)
VEHS_GRAM_LEVEL(avx512)
#undef VEHS_GRAM_LEVEL

namespace detail {

void add_AtB(const double* A, std::ptrdiff_t lda, const double* B, std::ptrdiff_t ldb, int m, int na, int nb,
             double* C, std::ptrdiff_t ldc, bool lower) {
  switch (sim::simd_level()) {
    case sim::SimdLevel::Scalar: return simd_scalar::add_AtB(A, lda, B, ldb, m, na, nb, C, ldc, lower);
    case sim::SimdLevel::Sse2: return simd_sse2::add_AtB(A, lda, B, ldb, m, na, nb, C, ldc, lower);
    case sim::SimdLevel::Avx2: return simd_avx2::add_AtB(A, lda, B, ldb, m, na, nb, C, ldc, lower);
    case sim::SimdLevel::Avx512: return simd_avx512::add_AtB(A, lda, B, ldb, m, na, nb, C, ldc, lower);
  }
}

}  // namespace detail
}  // namespace vehs::identify
