// vehs/core/record_phases.hpp: a model with one harmonic_forcing phase per record, read as a
// time origin per record. Exact identities; no statistics.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "vehs/core/error.hpp"
#include "vehs/core/record_phases.hpp"
#include "vehs/io/model_file.hpp"

namespace {

vehs::Model forced(double amplitude, double omega, double phase, std::vector<double> record_phases) {
  nlohmann::json j = nlohmann::json::parse(R"({"drift": {"x": 1.0, "x^3": -1.0, "y": -0.1}, "diffusion": {"1": 0.02}})");
  j["effects"] = {{{"name", "harmonic_forcing"}, {"params", {{"amplitude", amplitude}, {"omega", omega}, {"phase", phase}}}}};
  vehs::Model m = vehs::model_from_json(j, "test model");
  if (!record_phases.empty()) {
    m.fit = vehs::FitInfo{};
    m.fit->likelihood = vehs::LikelihoodFit{};
    m.fit->likelihood->record_phases = std::move(record_phases);
  }
  return m;
}

vehs::Dataset records(const std::vector<double>& t0s) {
  vehs::Dataset d;
  for (double t0 : t0s) {
    vehs::Record r;
    r.t0 = t0;
    r.dt = 0.1;
    r.offset = d.x.size();
    r.size = 3;
    d.x.values().insert(d.x.values().end(), {0.0, 0.1, 0.2});
    d.records.push_back(r);
  }
  return d;
}

}  // namespace

TEST_CASE("record phases: the time origin of a record gives its own phase at every sample", "[core][record_phases]") {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> U(-M_PI, M_PI);
  const std::vector<double> phases = {U(g), U(g), U(g), U(g)};
  const double omega = 1.37, shared = 0.4;
  const vehs::Model m = forced(0.1, omega, shared, phases);
  const vehs::Dataset d = records({0.0, 12.5, -3.0, 1e3});
  const std::vector<double> tau = vehs::forcing_time_origins(m, d, "test", true);
  REQUIRE(tau.size() == 4);
  for (std::size_t r = 0; r < 4; ++r)
    for (int k = 0; k < 1000; k += 37) {
      const double t = d.records[r].t0 + k * 0.1;
      // cos(ω(τ_r + k dt) + φ) = cos(ω t + φ_r), to rounding of ω·t (t up to 1100)
      CHECK(std::cos(omega * (tau[r] + k * 0.1) + shared) == Approx(std::cos(omega * t + phases[r])).margin(1e-12));
    }
  CHECK(vehs::leading_record_phases(m, 2, "test") == std::vector<double>(phases.begin(), phases.begin() + 2));
}

TEST_CASE("record phases: a shared phase keeps t0 - other record counts are refused", "[core][record_phases]") {
  const vehs::Dataset d = records({0.0, 5.0});
  CHECK(vehs::forcing_time_origins(forced(0.1, 1.0, 0.3, {}), d, "test") == std::vector<double>{0.0, 5.0});
  CHECK(vehs::leading_record_phases(forced(0.1, 1.0, 0.3, {}), 2, "test").empty());
  const vehs::Model three = forced(0.1, 1.0, 0.3, {0.1, 0.2, 0.3});
  CHECK_NOTHROW(vehs::forcing_time_origins(three, d, "test"));  // the leading records
  CHECK_THROWS_WITH(vehs::forcing_time_origins(three, d, "diagnose", true),
                    Catch::Contains("diagnose: the model has one harmonic_forcing phase per record for 3 records") &&
                        Catch::Contains("the data have 2"));
  CHECK_THROWS_WITH(vehs::leading_record_phases(three, 4, "score suspects"), Catch::Contains("score suspects:"));
  vehs::Model still = forced(0.1, 1.0, 0.3, {0.1, 0.2});
  still.effects[0].params["omega"] = 0.0;  // a model built in code, not validated
  CHECK_THROWS_WITH(vehs::forcing_time_origins(still, d, "x"), Catch::Contains("omega != 0"));
}
