// One uncertainty in a model file (issue 33): identify-vehs's `stderr` (drift, diffusion, the
// effects' stderr, and effect_params' for term-like effects) are the square roots of the
// diagonal of its `covariance`, which lists exactly those parameters, after a moment fit, a
// likelihood fit (with and without selection, with an effect, with sensor noise and its bias
// correction, with a harmonic forcing per record), and the likelihood's own covariance holds
// the same doubles. Checked on the JSON text as a reader of the file sees it.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "../likelihood/likelihood_fixtures.hpp"
#include "tool_runs.hpp"
#include "tools/tools.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;
using namespace vehs;

namespace {

fs::path work_dir() { return vehs_tool_test::work_dir("test_model_uncertainty_work"); }

/// Writes `d` and a config with `keys`, runs identify-vehs in-process, returns the model file's JSON.
nlohmann::json identified(const Dataset& d, const std::string& name, const std::string& keys) {
  const fs::path dir = work_dir();
  const fs::path data = dir / (name + ".csv"), cfg = dir / (name + ".json"), out = dir / (name + "_model.json");
  write_measurements(data.string(), d, WriteColumns{false, false, 17});
  std::ofstream(cfg) << R"({"data": ")" + data.string() + R"(", "output": ")" + out.string() + "\", " + keys + "}";
  fs::remove(out);
  std::string a0 = "identify-vehs", a1 = cfg.string(), a2 = "--quiet";
  char* argv[] = {a0.data(), a1.data(), a2.data()};
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  const int code = tools::identify_main(3, argv);
  std::cerr.rdbuf(old);
  INFO(err.str());
  REQUIRE(code == 0);
  return nlohmann::json::parse(std::ifstream(out));
}

/// The file's standard errors by covariance name: stderr.drift, stderr.diffusion, effects[].stderr.
std::map<std::string, double> file_stderrs(const nlohmann::json& f) {
  std::map<std::string, double> se;
  if (f.contains("stderr"))
    for (const char* part : {"drift", "diffusion"})
      if (f["stderr"].contains(part))
        for (auto it = f["stderr"][part].begin(); it != f["stderr"][part].end(); ++it)
          se[std::string(part) + "[" + it.key() + "]"] = it.value().get<double>();
  if (f.contains("effects"))
    for (const auto& e : f["effects"])
      if (e.is_object() && e.contains("stderr"))
        for (auto it = e["stderr"].begin(); it != e["stderr"].end(); ++it)
          se[e["name"].get<std::string>() + "." + it.key()] = it.value().get<double>();
  return se;
}

/// Every stderr is sqrt(diag(covariance)) (relative 1e-12) and both list the same parameters; a
/// likelihood fit's own covariance holds the same entries; effect_params' standard errors of
/// term-like effects are those of their terms.
void check_one_uncertainty(const nlohmann::json& f) {
  const auto se = file_stderrs(f);
  REQUIRE(!se.empty());
  REQUIRE(f.contains("covariance"));
  const auto& names = f["covariance"]["parameters"];
  const auto& C = f["covariance"]["matrix"];
  REQUIRE(names.size() == se.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string name = names[i].get<std::string>();
    INFO(name);
    REQUIRE(se.count(name) == 1);
    const double from_cov = std::sqrt(C[i][i].get<double>());
    CHECK(std::abs(se.at(name) - from_cov) <= 1e-12 * from_cov);
  }
  if (f.contains("likelihood")) {
    const auto& lp = f["likelihood"]["parameters"];
    const auto& LC = f["likelihood"]["covariance"];
    auto at = [&](const std::string& n) {
      for (std::size_t k = 0; k < lp.size(); ++k)
        if (lp[k] == n) return k;
      FAIL("likelihood.parameters lacks " << n);
      return std::size_t(0);
    };
    for (std::size_t i = 0; i < names.size(); ++i)
      for (std::size_t j = 0; j < names.size(); ++j) {
        INFO(names[i] << ", " << names[j]);
        CHECK(C[i][j].get<double>() == LC[at(names[i])][at(names[j])].get<double>());
      }
  }
  if (f.contains("effect_params"))
    for (const auto& e : f["effect_params"]) {
      if (e["name"] != "coulomb_friction" || !e.contains("stderr")) continue;
      CHECK(e["stderr"]["mu"].get<double>() == se.at("drift[sign(y)]"));
    }
}

Model friction_model() {
  return vehs_lik_test::model(
      R"j({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.1, "sign(y)": -0.08}, "diffusion": {"1": 0.04}})j");
}

const std::string kSmallLibrary =
    R"("drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none", )";

}  // namespace

TEST_CASE("a model file's stderr is sqrt(diag(covariance)): moment fit", "[tools][uncertainty]") {
  const Dataset d = vehs_lik_test::simulate(vehs_lik_test::bistable(), 0.05, 2, 200.0, 3);
  check_one_uncertainty(identified(d, "moment", R"("drift_library": ["1", "x", "x^2", "x^3", "y"],
      "diffusion_library": ["1", "x^2"], "likelihood": {"use": "never"})"));
}

TEST_CASE("a model file's stderr is sqrt(diag(covariance)): likelihood with and without selection",
          "[tools][uncertainty][likelihood]") {
  const Dataset d = vehs_lik_test::simulate(vehs_lik_test::bistable(), 0.5, 2, 1500.0, 5);
  check_one_uncertainty(identified(d, "lik_select", R"("drift_library": ["1", "x", "x^2", "x^3", "y"],
      "diffusion_library": ["1"], "sparsity": "none", "likelihood": {"use": "always", "measurement_noise": false})"));
  check_one_uncertainty(identified(d, "lik_fixed", kSmallLibrary +
      R"("likelihood": {"use": "always", "select": false, "measurement_noise": false})"));
}

TEST_CASE("a model file's stderr is sqrt(diag(covariance)): likelihood with coulomb_friction - and "
          "with sensor noise estimated and bias-corrected",
          "[tools][uncertainty][likelihood][effects]") {
  const Dataset d = vehs_lik_test::simulate(friction_model(), 0.5, 2, 1500.0, 7);
  check_one_uncertainty(identified(d, "lik_friction", kSmallLibrary +
      R"("effects": ["coulomb_friction"], "likelihood": {"use": "always", "select": false, "measurement_noise": false})"));
  const Dataset noisy = vehs_lik_test::simulate(vehs_lik_test::bistable(), 0.5, 2, 1500.0, 9, 0.05);
  check_one_uncertainty(identified(noisy, "lik_noise", kSmallLibrary +
      R"("likelihood": {"use": "always", "select": false, "measurement_noise": true, "bias_correction": 2})"));
}

TEST_CASE("a model file's stderr is sqrt(diag(covariance)): harmonic forcing by the profile fit and by the "
          "likelihood with one phase per record",
          "[tools][uncertainty][likelihood][effects]") {
  Dataset d;
  const double phases[] = {-2.0, 1.0};
  for (int r = 0; r < 2; ++r) {
    Model m = vehs_lik_test::bistable();
    Effect h;
    h.id = EffectId::HarmonicForcing;
    h.params = {{"amplitude", 0.12}, {"omega", 0.8}, {"phase", phases[r]}};
    add_effect(m, h, "test");
    d.append(vehs_lik_test::simulate(m, 0.25, 1, 750.0, 11 + std::uint64_t(r)));
    d.records.back().id = r;
  }
  check_one_uncertainty(identified(d, "forcing_moment", kSmallLibrary +
      R"("effects": ["harmonic_forcing"], "likelihood": {"use": "never"})"));
  check_one_uncertainty(identified(d, "forcing_phases", kSmallLibrary +
      R"("effects": ["harmonic_forcing"], "likelihood": {"use": "always", "select": false,
         "measurement_noise": false, "per_record_phase": true})"));
}
