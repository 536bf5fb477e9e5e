#pragma once
// Models with known stationary behaviour, used as fixtures by the FPK tests.
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "vehs/core/model.hpp"
#include "vehs/fpk/stationary.hpp"
#include "vehs/io/model_file.hpp"

namespace fpk_fixtures {

inline vehs::Model model(const std::string& json) {
  return vehs::model_from_json(nlohmann::json::parse(json), "fixture");
}

/// The paper's learned penta-stable model (Tables 2, 3) with diffusion 2D + 2Q x².
inline vehs::Model paper_learned(double two_d = 0.0194, double two_q = 0.0116) {
  return model(R"({"drift": {"x": -0.9976, "x^3": 7.7182, "x^5": -16.3409, "x^7": 12.5293,
                             "x^9": -3.1068, "y": -0.1010},
                   "diffusion": {"1": )" + std::to_string(two_d) + R"(, "x^2": )" +
               std::to_string(two_q) + "}}");
}

/// Exact density p ∝ exp(−(β0/D)(y²/2 + U(x))) of the models whose damping is
/// β(x) = β0 (1 + Q x²/D) and a22 = 2D + 2Q x² (Q = 0: the additive case), normalised with an
/// accurate quadrature of the x-integral (Simpson, 2e5 panels) and the exact Gaussian y-integral.
struct ExactDensity {
  const vehs::fpk::FpkModel& model;
  double beta0, D;
  double log_z = 0.0;
  ExactDensity(const vehs::fpk::FpkModel& m, double beta0_, double D_, double lo, double hi)
      : model(m), beta0(beta0_), D(D_) {
    const int n = 200000;
    const double h = (hi - lo) / n;
    double s = 0.0;
    for (int k = 0; k <= n; ++k) {
      const double x = lo + k * h;
      const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      s += w * std::exp(-beta0 * m.potential(x) / D);
    }
    s *= h / 3.0;
    log_z = std::log(s) + 0.5 * std::log(2.0 * M_PI * D / beta0);
  }
  double operator()(double x, double y) const {
    return std::exp(-(beta0 / D) * (0.5 * y * y + model.potential(x)) - log_z);
  }
};

/// L1 distance ∫|p − p_exact| (midpoint rule) of a solution to the exact density.
inline double l1_error(const vehs::fpk::StationaryResult& r, const ExactDensity& exact) {
  const auto& g = r.grid;
  double s = 0.0;
  for (int i = 0; i < g.x.n; ++i)
    for (int j = 0; j < g.y.n; ++j)
      s += std::abs(r.density[g.index(i, j)] - exact(g.x.center(i), g.y.center(j)));
  return s * g.cell_area();
}

}  // namespace fpk_fixtures
