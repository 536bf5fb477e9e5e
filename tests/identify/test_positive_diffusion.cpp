// The moment fit's diffusion is a variance rate: > 0 where the data go and >= 0 for large |x|
// (src/identify/positive_diffusion.hpp). Deterministic.
#include <catch2/catch.hpp>

#include "../../src/identify/positive_diffusion.hpp"

using namespace vehs;

namespace {

bool positive(std::vector<const char*> names, std::vector<double> coefs, double x_lo, double x_hi) {
  std::vector<Term> terms;
  for (const char* n : names) terms.push_back(Term::parse(n));
  Eigen::VectorXd q(static_cast<int>(coefs.size()));
  for (std::size_t j = 0; j < coefs.size(); ++j) q[static_cast<int>(j)] = coefs[j];
  return identify::detail::positive_on(identify::Dictionary(terms), q, {x_lo, x_hi, 1.0});
}

}  // namespace

TEST_CASE("positive diffusion: > 0 over the data and >= 0 for large x", "[identify][diffusion]") {
  // a positioning rig's few cm: 2D + c·x is > 0 there but negative beyond x = -0.069
  CHECK_FALSE(positive({"1", "x"}, {2.16e-5, 3.14e-4}, -0.02, 0.02));
  CHECK(positive({"1", "x^2"}, {2.16e-5, 3.14e-4}, -0.02, 0.02));
  CHECK(positive({"1", "x", "x^2"}, {0.04, 0.03, 0.02}, -2.0, 2.0));
  // a negative even leading power: > 0 over the data, negative for large |x|
  CHECK_FALSE(positive({"1", "x^4"}, {1.0, -0.1}, -1.5, 1.5));
  // negative inside the data
  CHECK_FALSE(positive({"1", "x^2"}, {-0.01, 1.0}, -1.0, 1.0));
}
