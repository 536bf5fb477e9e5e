#include <catch2/catch.hpp>

#include "vehs/core/error.hpp"
#include "vehs/core/model.hpp"
#include "vehs/io/model_file.hpp"

using nlohmann::json;

TEST_CASE("model JSON round-trips and exposes the paper's parameters", "[model]") {
  const auto j = json::parse(R"({
    "drift": {"x": -1.0, "x^3": 7.7, "x^5": -16.3, "x^7": 12.5, "x^9": -3.1, "y": -0.1},
    "diffusion": {"1": 0.02, "x^2": 0.01},
    "stderr": {"drift": {"x": 0.004}, "diffusion": {"1": 0.0001}},
    "provenance": {"tool": "test"}
  })");
  nlohmann::ordered_json sections;
  const auto m = vehs::model_from_json(j, "m.json", &sections);
  CHECK(-m.drift_coef("y") == 0.1);
  CHECK(-m.drift_coef("x^9") == Approx(3.1));
  CHECK(m.diffusion_coef("x^2") == 0.01);
  CHECK(m.drift_stderr.at("x") == 0.004);
  CHECK(m.b2(1.0, 0.5) == Approx(-1 + 7.7 - 16.3 + 12.5 - 3.1 - 0.05));
  CHECK(m.a22(2.0, 0.0) == Approx(0.06));
  nlohmann::ordered_json back_sections;
  const auto back = vehs::model_from_json(json::parse(vehs::model_to_json(m, sections).dump()), "again", &back_sections);
  CHECK(back.drift.size() == 6);
  CHECK(back_sections.at("provenance").at("tool") == "test");
  CHECK(!back.fit);
  CHECK(back.diffusion_stderr.at("1") == 0.0001);
}

TEST_CASE("term-like effects expand into terms, dynamic ones are kept", "[model]") {
  const auto m = vehs::model_from_json(json::parse(R"({
    "drift": {"x": -1.0, "y": -0.1}, "diffusion": {"1": 0.02},
    "effects": [{"name": "coulomb_friction", "params": {"mu": 0.03}},
                {"name": "impact_stop", "params": {"k_stop": 50, "gap": 1.2}},
                {"name": "velocity_dependent_noise", "params": {"q_y2": 0.005}}]
  })"), "m.json");
  CHECK(m.drift_coef("sign(y)") == -0.03);
  CHECK(m.diffusion_coef("y^2") == 0.005);
  REQUIRE(m.effects.size() == 1);
  CHECK(m.effects[0].name() == "impact_stop");
  CHECK(m.effects[0].param("gap_neg") == 1.2);
}

TEST_CASE("bad models are rejected with a message naming the problem", "[model]") {
  auto bad = [](const char* text) {
    return vehs::model_from_json(json::parse(text), "bad.json");
  };
  CHECK_THROWS_WITH(bad(R"({"drift": {"x": -1}})"), Catch::Contains("no 'diffusion'"));
  CHECK_THROWS_WITH(bad(R"({"drift": {"q": -1}, "diffusion": {}})"), Catch::Contains("unknown term 'q'"));
  CHECK_THROWS_WITH(bad(R"({"drift": {"x": "a"}, "diffusion": {}})"), Catch::Contains("must be a number"));
  CHECK_THROWS_WITH(bad(R"({"drift": {}, "diffusion": {}, "effects": [{"name": "magic"}]})"),
                    Catch::Contains("must be one of"));
  CHECK_THROWS_WITH(bad(R"({"drift": {}, "diffusion": {}, "effects": [{"name": "coulomb_friction"}]})"),
                    Catch::Contains("needs parameter 'mu'"));
  CHECK_THROWS_WITH(bad(R"J({"drift": {"sign(y)": -0.1}, "diffusion": {},
                            "effects": [{"name": "coulomb_friction", "params": {"mu": 0.1}}]})J"),
                    Catch::Contains("both as a term and through an effect"));
  CHECK_THROWS_WITH(bad(R"({"drift": {}, "diffusion": {},
                            "effects": [{"name": "impact_stop", "params": {"k_stop": -1, "gap": 1}}]})"),
                    Catch::Contains("must be > 0"));
  const auto m = bad(R"({"drift": {"x": -1}, "diffusion": {"1": -0.1}})");
  CHECK_THROWS_WITH(vehs::validate_model(m, "bad.json"), Catch::Contains("negative"));
}

TEST_CASE("the covariance of the estimates round-trips - a bad one is rejected naming the entry", "[model][covariance]") {
  const auto m = vehs::model_from_json(json::parse(R"({
    "drift": {"x": -1, "y": -0.1}, "diffusion": {"1": 0.02},
    "covariance": {"parameters": ["drift[x]", "drift[y]", "diffusion[1]"],
                   "matrix": [[1e-4, 2e-6, 0], [2e-6, 4e-6, 1e-8], [0, 1e-8, 1e-8]]}})"), "m.json");
  REQUIRE(m.covariance.size() == 3);
  CHECK(m.covariance(0, 1) == 2e-6);
  CHECK(m.covariance.index_of("diffusion[1]") == 2);
  const auto back = vehs::model_from_json(json::parse(vehs::model_to_json(m).dump()), "back.json");
  CHECK(back.covariance.names == m.covariance.names);
  CHECK(back.covariance.matrix == m.covariance.matrix);
  auto bad = [](const char* cov) {
    return vehs::model_from_json(
        json::parse(std::string(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02}, "covariance": )") + cov + "}"),
        "bad.json");
  };
  CHECK_THROWS_WITH(bad(R"({"parameters": ["drift[x]"], "matrix": [[null]]})"),
                    Catch::Contains("bad.json: covariance.matrix[0][0]"));
  CHECK_THROWS_WITH(bad(R"({"parameters": ["drift[x]", "drift[y]"], "matrix": [[1, 0.5], [0.4, 1]]})"),
                    Catch::Contains("not symmetric"));
  CHECK_THROWS_WITH(bad(R"({"parameters": ["drift[x]"], "matrix": [[-1]]})"), Catch::Contains("negative"));
  CHECK_THROWS_WITH(bad(R"({"parameters": ["drift[x]", "drift[x]"], "matrix": [[1, 0], [0, 1]]})"),
                    Catch::Contains("appears twice"));
}

TEST_CASE("the likelihood's bias correction is recorded in the model file and read back - bad entries are "
          "rejected naming the key",
          "[model][likelihood]") {
  auto with = [](const std::string& bias) {
    return vehs::model_from_json(
        json::parse(R"({"drift": {"x": -1}, "diffusion": {"1": 0.02}, "likelihood": {"measurement_sd": 0.01,
                    "parameters": ["drift[x]"], "values": [-1], "bias_correction": )" + bias + "}}"),
        "m.json");
  };
  const auto m = with(R"({"datasets": 8, "seed": 18446744073709551615, "max_shift_se": 0.75})");
  REQUIRE(m.fit);
  REQUIRE(m.fit->likelihood);
  const vehs::LikelihoodFit& lf = *m.fit->likelihood;
  CHECK(lf.bias_correction_datasets == 8);
  CHECK(lf.bias_correction_seed == 18446744073709551615ULL);
  CHECK(lf.bias_correction_max_shift_se == 0.75);
  const json back_json = json::parse(vehs::model_to_json(m).dump());
  CHECK(back_json["likelihood"]["bias_correction"] ==
        json::parse(R"({"datasets": 8, "seed": 18446744073709551615, "max_shift_se": 0.75})"));
  const auto back = vehs::model_from_json(back_json, "back.json");
  CHECK(back.fit->likelihood->bias_correction_seed == lf.bias_correction_seed);
  CHECK(back.fit->likelihood->bias_correction_max_shift_se == 0.75);
  // an automatic correction that was skipped says why; none asked: no key written
  const auto skipped = with(R"({"datasets": 0, "skipped": "cannot simulate the fitted model"})");
  CHECK(skipped.fit->likelihood->bias_correction_skipped == "cannot simulate the fitted model");
  CHECK(json::parse(vehs::model_to_json(skipped).dump())["likelihood"]["bias_correction"] ==
        json::parse(R"({"datasets": 0, "skipped": "cannot simulate the fitted model"})"));
  auto none = m;
  none.fit->likelihood->bias_correction_datasets = 0;
  CHECK(!json::parse(vehs::model_to_json(none).dump())["likelihood"].contains("bias_correction"));
  const std::pair<const char*, const char*> bad[] = {
      {R"(8)", "m.json: likelihood.bias_correction must be an object"},
      {R"({"seed": 1})", "likelihood.bias_correction.datasets is missing"},
      {R"({"datasets": -1})", "likelihood.bias_correction.datasets must be an integer in [0, 1000]"},
      {R"({"datasets": 1001})", "likelihood.bias_correction.datasets must be an integer in [0, 1000]"},
      {R"({"datasets": 2.5})", "likelihood.bias_correction.datasets must be an integer in [0, 1000]"},
      {R"({"datasets": 8, "seed": -3})", "likelihood.bias_correction.seed must be an integer >= 0"},
      {R"({"datasets": 8, "max_shift_se": -0.1})", "likelihood.bias_correction.max_shift_se must be >= 0"},
      {R"({"datasets": 8, "max_shift_se": "big"})", "likelihood.bias_correction.max_shift_se must be a number"},
      {R"({"datasets": 8, "skipped": 3})", "likelihood.bias_correction.skipped must be a string"},
      {R"({"datasets": 8, "sets": 8})", "likelihood.bias_correction: unknown key 'sets'"},
  };
  for (const auto& [text, message] : bad) {
    CAPTURE(text);
    CHECK_THROWS_WITH(with(text), Catch::Contains(message));
  }
}
