#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "vehs/core/error.hpp"
#include "vehs/core/model_builder.hpp"
#include "vehs/core/parameters.hpp"
#include "vehs/io/model_file.hpp"

namespace {

// The model written as a file states it term by term; the C++ routes must give the same Model.
std::string as_json(const vehs::Model& m) { return vehs::model_to_json(m).dump(); }

}  // namespace

TEST_CASE("Model::paper and the builder give the model a file states", "[model_builder]") {
  const vehs::Model from_file = vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
    "diffusion": {"1": 0.02, "x^2": 0.01}})"),
                                                      "paper");
  const vehs::Model paper =
      vehs::Model::paper(0.1, {{1, 1.0}, {3, -7.7}, {5, 16.3}, {7, -12.5}, {9, 3.1}}, 0.02, 0.01);
  CHECK(as_json(paper) == as_json(from_file));
  // terms in any order, by name, give the canonical model
  const vehs::Model built = vehs::ModelBuilder("built")
                                .diffusion("x^2", 0.01)
                                .drift("x^9", -3.1)
                                .drift("y", -0.1)
                                .drift("x^3", 7.7)
                                .parameter("k1", 1.0)
                                .parameter("k5", 16.3)
                                .parameter("k7", -12.5)
                                .parameter("D", 0.01)
                                .build();
  CHECK(as_json(built) == as_json(from_file));
}

TEST_CASE("the builder expands term-like effects and keeps dynamic ones, as a file does", "[model_builder]") {
  const vehs::Model from_file = vehs::model_from_json(nlohmann::json::parse(R"({
    "drift": {"x": -1.0, "y": -0.2}, "diffusion": {"1": 0.05},
    "effects": [{"name": "coulomb_friction", "params": {"mu": 0.03}},
                {"name": "impact_stop", "params": {"k_stop": 50.0, "gap": 1.2}}]})"),
                                                      "effects");
  const vehs::Model built = vehs::ModelBuilder()
                                .parameter("beta", 0.2)
                                .parameter("k1", 1.0)
                                .parameter("2D", 0.05)
                                .effect("coulomb_friction", {{"mu", 0.03}})
                                .effect("impact_stop", {{"k_stop", 50.0}, {"gap", 1.2}})
                                .build();
  CHECK(as_json(built) == as_json(from_file));
  CHECK(built.drift_coef("sign(y)") == -0.03);
  REQUIRE(built.find_effect(vehs::EffectId::ImpactStop) != nullptr);
  CHECK(built.find_effect(vehs::EffectId::ImpactStop)->param("gap_neg") == 1.2);  // defaults to gap
  CHECK(vehs::get_parameter(built, "impact_stop.k_stop") == 50.0);
}

TEST_CASE("the builder rejects what a model file would reject, naming the problem", "[model_builder]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto message = [](auto&& build) -> std::string {
    try {
      build();
    } catch (const vehs::Error& e) {
      return e.what();
    }
    return "";
  };
  using B = vehs::ModelBuilder;
  CHECK_THAT(message([] { B("m").drift("x^^2", 1.0); }), Catch::Contains("m: drift"));
  CHECK_THAT(message([] { B("m").drift("x", -1.0).drift("x", -2.0); }), Catch::Contains("m: drift: term 'x' appears twice"));
  CHECK_THAT(message([&] { B("m").drift("x", nan); }), Catch::Contains("must be finite"));
  CHECK_THAT(message([] { B("m").diffusion("sign(y)", 0.1); }), Catch::Contains("not allowed"));
  CHECK_THAT(message([] { B("m").diffusion("u", 0.1); }), Catch::Contains("not allowed"));
  CHECK_THAT(message([] { B("m").parameter("gamma", 1.0); }), Catch::Contains("gamma"));
  CHECK_THAT(message([&] { B("m").parameter("beta", nan); }), Catch::Contains("finite"));
  CHECK_THAT(message([] { B("m").effect("magnetic_levitation"); }), Catch::Contains("magnetic_levitation"));
  CHECK_THAT(message([] { B("m").effect("impact_stop", {{"gap", 1.0}}); }), Catch::Contains("k_stop"));
  CHECK_THAT(message([] { B("m").effect("coulomb_friction", {{"mu", 0.1}, {"nu", 1.0}}); }),
             Catch::Contains("nu"));
  CHECK_THAT(message([] { B("m").effect("impact_stop", {{"k_stop", -1.0}, {"gap", 1.0}}); }),
             Catch::Contains("k_stop must be > 0"));
  CHECK_THAT(message([] { B("m").drift("sign(y)", -0.1).effect("coulomb_friction", {{"mu", 0.1}}); }),
             Catch::Contains("both as a term and through an effect"));
  CHECK_THAT(message([] { B("m").parameter("2D", -0.1).build(); }), Catch::Contains("m: diffusion a22(0, 0)"));
  CHECK_THAT(message([] {
               B("m").parameter("2D", 0.1).effect("impact_stop", {{"k_stop", 1.0}, {"gap", 1.0}}).effect(
                   "impact_stop", {{"k_stop", 2.0}, {"gap", 1.0}});
             }),
             Catch::Contains("given twice"));
}
