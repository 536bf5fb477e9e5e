// The one-step prediction of an OU excitation from a record's past (colored_noise; diagnose's
// held-out score of the suspect uses it).
#include <algorithm>
#include <cmath>

#include "vehs/identify/dynamic.hpp"

namespace vehs::identify {

void colored_prediction(const Effect& colored, const TermList& drift, const TermList& diffusion,
                        const double* x, const double* u, std::size_t n, double dt, int k,
                        std::vector<double>& eta_pred) {
  eta_pred.assign(n, 0.0);
  const auto K = static_cast<std::size_t>(std::max(k, 1));
  if (n < 4 * K + 2) return;
  const double h = static_cast<double>(K) * dt;
  const double tau = colored.param("tau"), I = colored.param("intensity");
  const double s2 = I / (2.0 * tau);
  const double p1 = std::exp(-dt / tau), q1 = s2 * (1.0 - p1 * p1);
  const double pk2 = std::exp(-2.0 * h / tau);
  double m = 0.0, P = s2;
  double rfloor = 0.0;
  for (std::size_t i = K; i + K < n; ++i) {
    const double xi = x[i], v = (x[i + K] - x[i - K]) / (2 * h);
    const double a = (x[i + K] - 2 * x[i] + x[i - K]) / (h * h);
    const double r = a - evaluate(drift, xi, v, u ? u[i] : 0.0);
    double R = evaluate(diffusion, xi, v, 0.0) / dt;  // long-run variance of the ULI noise per row
    if (rfloor == 0.0) rfloor = std::max(1e-12, 1e-3 * std::abs(R));
    R = std::max(R, rfloor);
    if (i > K) {
      m *= p1;
      P = p1 * p1 * P + q1;
    }
    const double g = P / (P + R);
    m += g * (r - m);
    P *= (1.0 - g);
    if (i + 2 * K < n) eta_pred[i + 2 * K] = pk2 * m;
  }
}

}  // namespace vehs::identify
