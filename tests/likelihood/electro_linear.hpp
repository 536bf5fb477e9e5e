#pragma once
// A LINEAR coupled oscillator with the electromechanical state, simulated by its exact
// discretisation (Van Loan's matrix exponential), every record started from the stationary law
// (the Lyapunov equation solved by Kronecker products): a route the likelihood's filter never
// uses, on which that filter is an exact Kalman filter. Used by test_electro_prior.cpp and the
// hidden bench tests/diagnose/test_emc_bias.cpp.
#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "vehs/core/dataset.hpp"
#include "vehs/core/model.hpp"
#include "vehs/io/model_file.hpp"

namespace electro_linear {

// ẍ = −ω² x − β ẋ − κ v + σ ξ,  v̇ = ẋ − λ v
constexpr double kOmega2 = 2.0, kBeta = 0.1, kKappa = 0.5, kLambda = 0.8, kQ = 0.04;

inline Eigen::Matrix3d drift_matrix() {
  Eigen::Matrix3d F;
  F << 0, 1, 0, -kOmega2, -kBeta, -kKappa, 0, 1, -kLambda;
  return F;
}

/// The stationary covariance of (x, y, v): F Σ + Σ Fᵀ + Q = 0.
inline Eigen::Matrix3d stationary_covariance() {
  const Eigen::Matrix3d F = drift_matrix(), I = Eigen::Matrix3d::Identity();
  Eigen::Matrix<double, 9, 9> K;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K.block<3, 3>(3 * i, 3 * j) = F(i, j) * I + (i == j ? F : Eigen::Matrix3d::Zero());
  Eigen::Matrix<double, 9, 1> q = Eigen::Matrix<double, 9, 1>::Zero();
  q[4] = -kQ;  // Σ(1, 1) in column-major vec
  const Eigen::Matrix<double, 9, 1> s = K.fullPivLu().solve(q);
  return Eigen::Map<const Eigen::Matrix3d>(s.data());
}

/// Records of the linear model by its exact discretisation, each started stationary.
inline vehs::Dataset exact_records(int records, std::size_t samples, double dt, std::uint64_t seed) {
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  M.topLeftCorner<3, 3>() = -drift_matrix() * dt;
  M(1, 4) = kQ * dt;
  M.bottomRightCorner<3, 3>() = drift_matrix().transpose() * dt;
  const Eigen::Matrix<double, 6, 6> G = M.exp();
  const Eigen::Matrix3d A = G.bottomRightCorner<3, 3>().transpose();
  const Eigen::Matrix3d Qd = A * G.topRightCorner<3, 3>();
  const Eigen::Matrix3d Lq = Eigen::LLT<Eigen::Matrix3d>(0.5 * (Qd + Qd.transpose())).matrixL();
  const Eigen::Matrix3d Ls = Eigen::LLT<Eigen::Matrix3d>(stationary_covariance()).matrixL();
  std::mt19937_64 g(seed);
  std::normal_distribution<double> n01;
  auto normal3 = [&] { return Eigen::Vector3d(n01(g), n01(g), n01(g)); };
  vehs::Dataset d;
  std::vector<double> x;
  for (int r = 0; r < records; ++r) {
    Eigen::Vector3d s = Ls * normal3();
    for (std::size_t k = 0; k < samples; ++k) {
      x.push_back(s[0]);
      s = A * s + Lq * normal3();
    }
    vehs::Record rec;
    rec.id = r;
    rec.dt = dt;
    rec.offset = std::size_t(r) * samples;
    rec.size = samples;
    d.records.push_back(rec);
  }
  d.x = vehs::Column(std::move(x));
  return d;
}

inline vehs::Model linear_model() {
  vehs::Model m = vehs::model_from_json(
      nlohmann::json::parse(R"({"drift": {"x": -2.0, "y": -0.1}, "diffusion": {"1": 0.04}})"), "linear oscillator");
  vehs::Effect e;
  e.id = vehs::EffectId::ElectromechanicalCoupling;
  e.params = {{"lambda", kLambda}, {"coupling", kKappa}};
  m.effects = {e};
  return m;
}

}  // namespace electro_linear
