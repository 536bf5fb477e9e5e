// identify's Gram kernel (vehs/identify/gram.hpp): C += Aᵀ·B against Eigen's product, and every
// SIMD level this CPU runs (vehs/sim/simd.hpp) bitwise equal to the scalar level (one source,
// the same IEEE operations in the same order, no fused multiply-add). Deterministic: no
// statistical tolerance.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "vehs/identify/gram.hpp"
#include "vehs/sim/simd.hpp"

using vehs::sim::SimdLevel;

namespace {

constexpr SimdLevel kAll[] = {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512};

struct LevelGuard {
  SimdLevel saved = vehs::sim::simd_level();
  ~LevelGuard() { vehs::sim::set_simd_level(saved); }
};

Eigen::MatrixXd random_block(int rows, int cols, unsigned seed) {
  std::mt19937_64 g(seed);
  std::normal_distribution<double> n;
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = std::ldexp(n(g), static_cast<int>(j % 5) - 2);
  return m;
}

/// C0 + Aᵀ·B by the kernel at `level` (rows m of A and B; `lower`: A == B, lower triangle).
Eigen::MatrixXd gram_at(SimdLevel level, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, int m,
                        const Eigen::MatrixXd& C0, bool lower) {
  vehs::sim::set_simd_level(level);
  Eigen::MatrixXd C = C0;
  vehs::identify::add_gram(A, B, m, C, lower);
  return C;
}

}  // namespace

TEST_CASE("Gram kernel: C += A^T B within rounding of Eigen's product, bitwise equal at every SIMD level",
          "[identify][gram][simd]") {
  LevelGuard guard;
  for (int m : {1, 3, 4, 7, 64, 257}) {
    for (auto [na, nb] : {std::pair{1, 1}, std::pair{5, 3}, std::pair{13, 13}, std::pair{30, 2}}) {
      for (bool lower : {false, true}) {
        if (lower && na != nb) continue;
        CAPTURE(m, na, nb, lower);
        const Eigen::MatrixXd A = random_block(m + 5, na, 17u * static_cast<unsigned>(m) + static_cast<unsigned>(na));
        const Eigen::MatrixXd B = lower ? A : random_block(m + 5, nb, 31u * static_cast<unsigned>(m) + 7u);
        const Eigen::MatrixXd C0 = random_block(na, nb, 5u);
        const Eigen::MatrixXd scalar = gram_at(SimdLevel::Scalar, A, B, m, C0, lower);
        // rows ≥ m of A and B are not read; the upper triangle is left alone with `lower`
        const Eigen::MatrixXd exact = C0 + A.topRows(m).transpose() * B.topRows(m);
        const Eigen::MatrixXd bound =
            C0.cwiseAbs() + A.topRows(m).cwiseAbs().transpose() * B.topRows(m).cwiseAbs();
        const double gamma = (m + 2) * std::numeric_limits<double>::epsilon();  // m + 1 roundings per sum
        for (int j = 0; j < nb; ++j)
          for (int i = 0; i < na; ++i) {
            if (lower && i < j) {
              CHECK(scalar(i, j) == C0(i, j));
              continue;
            }
            CHECK(std::abs(scalar(i, j) - exact(i, j)) <= gamma * bound(i, j));
          }
        for (SimdLevel level : kAll) {
          if (!vehs::sim::simd_level_supported(level)) continue;
          INFO("level " << vehs::sim::simd_level_name(level));
          const Eigen::MatrixXd c = gram_at(level, A, B, m, C0, lower);
          CHECK(std::memcmp(c.data(), scalar.data(), sizeof(double) * static_cast<std::size_t>(c.size())) == 0);
        }
      }
    }
  }
}
