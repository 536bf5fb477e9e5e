#include <catch2/catch.hpp>

#include "vehs/core/error.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/io/model_file.hpp"

TEST_CASE("physical parameter names map to term coefficients with the paper's signs", "[parameters]") {
  auto m = vehs::model_from_json(nlohmann::json::parse(R"J({
    "drift": {"x": -1.0, "x^3": 7.7, "y": -0.1, "sign(y)": -0.03},
    "diffusion": {"1": 0.02, "x^2": 0.01},
    "stderr": {"drift": {"y": 0.004}}})J"), "m");
  CHECK(vehs::get_parameter(m, "beta") == 0.1);
  CHECK(vehs::get_parameter(m, "k3") == -7.7);
  CHECK(vehs::get_parameter(m, "k5") == 0.0);
  CHECK(vehs::get_parameter(m, "2Q") == 0.01);
  CHECK(vehs::get_parameter(m, "drift[sign(y)]") == -0.03);
  vehs::set_parameter(m, "k5", 16.3);
  CHECK(m.drift_coef("x^5") == -16.3);
  vehs::set_parameter(m, "2D", 0.05);
  CHECK(m.diffusion_coef("1") == 0.05);
  const auto ps = vehs::physical_parameters(m);
  REQUIRE(ps.size() == 7);
  CHECK(ps[0].name == "beta");
  CHECK(ps[0].stderr_.value() == 0.004);
  CHECK(ps[1].name == "k1");
  CHECK(ps[3].name == "k5");
  CHECK(ps[4].name == "drift[sign(y)]");
  CHECK(ps[5].name == "2D");
  CHECK_THROWS_AS(vehs::get_parameter(m, "gamma"), vehs::Error);
}
