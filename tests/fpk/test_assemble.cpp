// The FPK assembler is a header kernel over any provider of b2 and a22 (vehs/fpk/assemble.hpp):
// a user's own coefficients give the same operator as the model they describe, and the operator
// conserves mass exactly (every column of a flux operator sums to zero).
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "fpk_fixtures.hpp"
#include "vehs/fpk/assemble.hpp"

using namespace vehs::fpk;

namespace {

/// A Duffing oscillator with multiplicative noise written directly: b2 = x − x³ − 0.2 y,
/// a22 = 0.02 + 0.01 x².
struct UserCoefficients {
  double b2(double x, double y) const { return x - x * x * x - 0.2 * y; }
  double db2_dy(double, double) const { return -0.2; }
  double a22(double x, double) const { return 0.02 + 0.01 * x * x; }
  double da22_dy(double, double) const { return 0.0; }
  double d2a22_dy2(double, double) const { return 0.0; }
  bool has_sign_y() const { return false; }
  std::string where() const { return "user coefficients"; }
};

}  // namespace

TEST_CASE("the FPK operator of a user's coefficients equals that of the same model", "[fpk][assemble]") {
  const FpkModel model(fpk_fixtures::model(R"({"drift": {"x": 1, "x^3": -1, "y": -0.2},
                                               "diffusion": {"1": 0.02, "x^2": 0.01}})"));
  Grid grid;
  grid.x = {-2.0, 2.0, 24};
  grid.y = {-1.5, 1.5, 20};
  for (const Scheme scheme : {Scheme::Flux, Scheme::Flux2, Scheme::Central}) {
    CAPTURE(vehs::enum_to_string(kSchemeNames, scheme));
    const SparseMatrix a = assemble_operator(model, grid, scheme);
    const SparseMatrix b = assemble_operator(UserCoefficients{}, grid, scheme);
    REQUIRE(a.nonZeros() == b.nonZeros());
    CHECK((a - b).norm() <= 1e-12 * a.norm());
    if (scheme != Scheme::Central) {
      // conservative: the columns sum to zero (total mass is conserved exactly)
      const Eigen::RowVectorXd sums = Eigen::RowVectorXd::Ones(a.rows()) * a;
      CHECK(sums.cwiseAbs().maxCoeff() <= 1e-12 * a.cwiseAbs().sum() / a.cols());
    }
  }
}
