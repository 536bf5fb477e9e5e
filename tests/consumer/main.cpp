// Builds a model through the public API and prints one derived number; exits 0 on success.
#include <cmath>
#include <cstdio>

#include <vehs/io/model_file.hpp>
#include <vehs/vehs.hpp>

int main() {
  const auto model = vehs::model_from_json(
      nlohmann::json::parse(R"({"drift": {"x": -1.0, "y": -0.1}, "diffusion": {"1": 0.02}})"),
      "consumer");
  // linear oscillator: E[X^2] = D / (beta k1) with D = a22/2
  const double beta = -model.drift_coef("y"), k1 = -model.drift_coef("x");
  const double ex2 = 0.5 * model.diffusion_coef("1") / (beta * k1);
  std::printf("E[X^2] = %.3f\n", ex2);
  return std::abs(ex2 - 0.1) < 1e-12 ? 0 : 1;
}
