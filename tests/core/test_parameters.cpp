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
  CHECK(ps[4].name == "coulomb_friction.mu");
  CHECK(ps[4].value == 0.03);
  CHECK(ps[4].coefficient == "drift[sign(y)]");
  CHECK(ps[5].name == "2D");
  CHECK_THROWS_AS(vehs::get_parameter(m, "gamma"), vehs::Error);
}

TEST_CASE("term-like effect parameters are read and set by their physical names", "[parameters]") {
  auto m = vehs::model_from_json(nlohmann::json::parse(R"J({
    "drift": {"x": -1.0, "y": -0.1, "sign(y)": -0.03, "y*|y|": -0.2, "y^3": -0.4},
    "diffusion": {"1": 0.02, "y^2": 0.5},
    "stderr": {"drift": {"sign(y)": 0.004}}})J"), "m");
  CHECK(vehs::get_parameter(m, "coulomb_friction.mu") == 0.03);
  CHECK(vehs::get_parameter(m, "mu") == 0.03);
  CHECK(vehs::get_parameter(m, "quadratic_damping.c") == 0.2);
  CHECK(vehs::get_parameter(m, "c_y3") == 0.4);
  CHECK(vehs::get_parameter(m, "nonlinear_damping.c_x2y") == 0.0);
  CHECK(vehs::get_parameter(m, "velocity_dependent_noise.q_y2") == 0.5);
  CHECK(vehs::get_parameter(m, "asymmetric_stiffness.k0") == 0.0);
  vehs::set_parameter(m, "mu", 0.07);
  CHECK(m.drift_coef("sign(y)") == -0.07);
  vehs::set_parameter(m, "nonlinear_damping.c_x2y", 0.3);
  CHECK(m.drift_coef("x^2*y") == -0.3);
  vehs::set_parameter(m, "asymmetric_stiffness.k2", 0.6);
  CHECK(m.drift_coef("x^2") == -0.6);
  const auto ps = vehs::physical_parameters(m);
  auto find = [&](const std::string& n) {
    for (const auto& p : ps)
      if (p.name == n) return p;
    FAIL("no parameter " << n);
    return ps.front();
  };
  CHECK(find("coulomb_friction.mu").value == 0.07);
  CHECK(find("coulomb_friction.mu").stderr_.value() == 0.004);
  CHECK(find("quadratic_damping.c").value == 0.2);
  CHECK(find("nonlinear_damping.c_x2y").value == Approx(0.3));
  CHECK(find("velocity_dependent_noise.q_y2").coefficient == "diffusion[y^2]");
  CHECK(find("k2").value == 0.6);
  // a dynamic effect's parameter still needs the effect; an unknown one is named
  CHECK_THROWS_WITH(vehs::get_parameter(m, "gap"), Catch::Contains("no effect 'impact_stop'"));
  CHECK_THROWS_WITH(vehs::get_parameter(m, "coulomb_friction.nu"), Catch::Contains("has no parameter 'nu'"));
  CHECK_THROWS_WITH(vehs::get_parameter(m, "nu"), Catch::Contains("unknown parameter 'nu'"));
}

TEST_CASE("parameter dimensions follow the data's units of length and time", "[parameters]") {
  auto dim = [](const std::string& n) {
    const vehs::Dimension d = vehs::parameter_dimension(n);
    return std::vector<int>{d.length, d.time, d.input};
  };
  CHECK(dim("beta") == std::vector<int>{0, -1, 0});
  CHECK(dim("k3") == std::vector<int>{-2, -2, 0});
  CHECK(dim("mu") == std::vector<int>{1, -2, 0});
  CHECK(dim("quadratic_damping.c") == std::vector<int>{-1, 0, 0});
  CHECK(dim("2D") == std::vector<int>{2, -3, 0});
  CHECK(dim("2Q") == std::vector<int>{0, -3, 0});
  CHECK(dim("drift[u]") == std::vector<int>{1, -2, -1});
  CHECK(dim("impact_stop.gap") == std::vector<int>{1, 0, 0});
  CHECK(dim("colored_noise.tau") == std::vector<int>{0, 1, 0});
}
