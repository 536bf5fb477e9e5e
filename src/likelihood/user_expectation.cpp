#include "vehs/likelihood/detail/user_expectation.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace vehs::likelihood::detail::user_detail {

namespace {

/// Golub–Welsch: the probabilists' Hermite rule of order 12 from its Jacobi matrix.
struct Rule {
  std::array<double, 12> nodes{}, weights{};
  Rule() {
    Eigen::Matrix<double, 12, 12> J = Eigen::Matrix<double, 12, 12>::Zero();
    for (int k = 1; k < 12; ++k) J(k, k - 1) = J(k - 1, k) = std::sqrt(double(k));
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> es(J);
    for (int k = 0; k < 12; ++k) {
      nodes[std::size_t(k)] = es.eigenvalues()(k);
      const double v = es.eigenvectors()(0, k);
      weights[std::size_t(k)] = v * v;
    }
  }
};

const Rule& rule() {
  static const Rule r;
  return r;
}

}  // namespace

const std::array<double, 12>& hermite_nodes() { return rule().nodes; }
const std::array<double, 12>& hermite_weights() { return rule().weights; }

}  // namespace vehs::likelihood::detail::user_detail
