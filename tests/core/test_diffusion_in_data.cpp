// The lowest diffusion over the data's states (vehs/core/diffusion_in_data.hpp): exact on a
// hand-made record, velocity from the central difference at the stride or the velocity column.
#include <catch2/catch.hpp>

#include <cmath>

#include "vehs/core/diffusion_in_data.hpp"

namespace {

/// One record x_i = A sin(ω i Δt), sampled densely.
vehs::Dataset sine(double A, double omega, double dt, std::size_t n) {
  vehs::Dataset d;
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = A * std::sin(omega * dt * static_cast<double>(i));
  d.x = vehs::Column(std::move(x));
  vehs::Record r;
  r.source = "sine.csv";
  r.first_line = 2;
  r.dt = dt;
  r.size = n;
  d.records.push_back(r);
  return d;
}

}  // namespace

TEST_CASE("a22 = 1 - x^2 on a sine of amplitude 2: lowest -3 at the crest, negative where |x| > 1",
          "[core][diffusion_in_data][asan]") {
  vehs::Model m;
  m.diffusion = {{vehs::Term::monomial(0), 1.0}, {vehs::Term::monomial(2), -1.0}};
  const std::size_t n = 4001;  // 2 periods at 1000 samples each
  const vehs::Dataset d = sine(2.0, 2.0 * M_PI / 2000.0, 1.0, n);
  const auto low = vehs::lowest_diffusion_in_data(m, d, 1);
  CHECK(low.samples == n - 2);
  CHECK(low.a22 == Approx(-3.0).margin(1e-4));
  CHECK(std::abs(low.x) == Approx(2.0).margin(1e-4));
  // |sin| > 1/2 on 2/3 of a period
  CHECK(double(low.negative) / double(low.samples) == Approx(2.0 / 3.0).margin(2e-3));
  m.diffusion = {{vehs::Term::monomial(0), 5.0}, {vehs::Term::monomial(2), -1.0}};
  CHECK(vehs::lowest_diffusion_in_data(m, d, 1).negative == 0);
}

TEST_CASE("a y-dependent diffusion reads the central-difference velocity at the stride",
          "[core][diffusion_in_data][asan]") {
  vehs::Model m;
  m.diffusion = {{vehs::Term::monomial(0), 1.0}, {vehs::Term::monomial(0, 2), -1.0}};  // 1 - y²
  const double A = 2.0, omega = 0.01;  // velocity amplitude 0.02: a22 >= 1 - 4e-4
  const vehs::Dataset d = sine(A, omega, 1.0, 2000);
  for (int k : {1, 7}) {
    const auto low = vehs::lowest_diffusion_in_data(m, d, k);
    CHECK(low.samples == 2000 - 2 * static_cast<std::size_t>(k));
    CHECK(low.negative == 0);
    CHECK(low.a22 == Approx(1.0 - A * A * omega * omega).margin(1e-5));
  }
}
