// The diffusion-domain rule every tool applies (vehs/core/diffusion_domain.hpp).
#include <catch2/catch.hpp>

#include <string>

#include "vehs/core/diffusion_domain.hpp"
#include "vehs/io/model_file.hpp"

namespace {
std::string why(const std::string& json) {
  return vehs::diffusion_negative_at_large_x(vehs::model_from_json(nlohmann::json::parse(json), "m"));
}
}  // namespace

TEST_CASE("diffusion negative for large |x| is found wherever the model is used", "[diffusion_domain]") {
  // the outside trial's model: fpk-stationary solved it (E[X^2] = 0.0789) where simulate-vehs
  // and diagnose-vehs refused it
  const std::string e = why(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02, "x^2": -0.01}})");
  CHECK(e.find("diffusion a22(x, 0) = 0.02 - 0.01·x^2 has leading term -0.01·x^2") != std::string::npos);
  CHECK(e.find("turns negative at |x| = 1.414") != std::string::npos);
  CHECK(e.find('\n') == std::string::npos);
  CHECK(why(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02, "x": 0.5}})").find("turns negative at x = -0.04") !=
        std::string::npos);
  CHECK(why(R"({"drift": {"x": -1}, "diffusion": {"1": -0.02}})").find("a22(x, 0) = -0.02 is negative") !=
        std::string::npos);
  // allowed: an even leading power with a positive coefficient, terms that vanish at y = 0
  CHECK(why(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02, "x^2": 0.01}})").empty());
  CHECK(why(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02, "x^2": -0.01, "x^4": 0.001}})").empty());
  CHECK(why(R"({"drift": {"x": -1}, "diffusion": {"y^2": 0.02}})").empty());
}
