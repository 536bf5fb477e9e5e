#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vehs/core/statistics.hpp"

TEST_CASE("batch means give an honest standard error for an AR(1) series", "[statistics]") {
  // AR(1) with phi = 0.9: the variance of the mean is (1+phi)/(1-phi) = 19 times the iid value.
  const double phi = 0.9;
  const std::size_t n = 200000;
  int covered = 0;
  const int reps = 40;
  for (int rep = 0; rep < reps; ++rep) {
    std::mt19937_64 g(static_cast<unsigned>(rep + 1));
    std::normal_distribution<double> z;
    std::vector<double> v(n);
    double s = 0;
    for (auto& e : v) e = s = phi * s + z(g);
    const auto est = vehs::batch_mean(v.data(), n, 50);
    const double iid_se = std::sqrt(1.0 / (1 - phi * phi) / static_cast<double>(n));
    CHECK(est.stderr_ > 3 * iid_se);  // an iid formula would be 4.4x too small
    covered += std::abs(est.value) < 1.96 * est.stderr_;
  }
  CHECK(covered >= 33);  // nominal 95 % of 40 = 38; binomial 1st percentile ~ 34
}

TEST_CASE("autocorrelation and Welch spectrum of an AR(1) series match theory", "[statistics]") {
  const double phi = 0.6, dt = 0.1;
  const std::size_t n = 1 << 18;
  std::mt19937_64 g(7);
  std::normal_distribution<double> z;
  std::vector<double> v(n);
  double s = 0;
  for (auto& e : v) e = s = phi * s + z(g);
  const auto rho = vehs::autocorrelation(v.data(), n, 5);
  for (int k = 0; k <= 5; ++k) CHECK(rho[static_cast<std::size_t>(k)] == Approx(std::pow(phi, k)).margin(0.01));
  const auto sp = vehs::welch_spectrum(v.data(), n, dt, 256);
  // one-sided PSD of AR(1) with unit innovations: 2 dt / |1 - phi e^{-i w dt}|^2
  for (std::size_t k : {5u, 40u, 100u}) {
    const double w = 2 * M_PI * sp.frequency[k] * dt;
    const double exact = 2 * dt / (1 + phi * phi - 2 * phi * std::cos(w));
    CHECK(sp.density[k] == Approx(exact).epsilon(0.08));
  }
}

TEST_CASE("histograms integrate to the inside fraction; Hellinger distance bounds", "[statistics]") {
  vehs::Histogram1D h(-1, 1, 20);
  for (int i = 0; i < 1000; ++i) h.add(-1.5 + 3.0 * i / 1000.0);
  double integral = 0;
  for (double d : h.density()) integral += d * h.width();
  CHECK(integral == Approx(1.0 - h.outside / h.total));
  CHECK(vehs::hellinger_distance({1, 2, 3}, {2, 4, 6}) == Approx(0.0).margin(1e-12));
  CHECK(vehs::hellinger_distance({1, 0}, {0, 1}) == Approx(1.0));
}
