// identify-vehs with the default config on a driven rig (issue 33): a recorded input column enters
// the default drift library as u (and the output says so), a given library without u is warned
// about, and under estimator auto the likelihood starts from every moment fit and keeps the
// highest log-likelihood (the model file lists the starts).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>

#include "../likelihood/likelihood_fixtures.hpp"
#include "tool_runs.hpp"
#include "tools/tools.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"

namespace fs = std::filesystem;
using namespace vehs;

namespace {

fs::path work_dir() { return vehs_tool_test::work_dir("test_identify_defaults_work"); }

using vehs_tool_test::run_identify;

/// The driven linear oscillator x'' = -x - 0.2 x' + 0.5 u + sqrt(0.02) dW/dt, integrated by
/// Euler-Maruyama at 1/50 of the sampling interval 0.05 (a sensor sampling a continuous process),
/// with u a sum of four sines of random phases recorded at the samples. Not the library's simulator.
constexpr double kDrive = 0.5;
Dataset driven_oscillator(int records, double duration, std::uint64_t seed) {
  const double dt = 0.05, k = 1.0, c = 0.2, a22 = 0.02;
  const int sub = 50;
  const double h = dt / sub;
  const double freq[] = {0.3, 0.7, 1.3, 2.1};
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  Dataset d;
  const auto n = static_cast<std::size_t>(duration / dt);
  std::vector<double> xs, us;
  for (int r = 0; r < records; ++r) {
    double ph[4];
    for (double& p : ph) p = phase(gen);
    const auto u = [&](double t) {
      double s = 0.0;
      for (int i = 0; i < 4; ++i) s += std::cos(freq[i] * t + ph[i]);
      return s;
    };
    double x = 0.0, y = 0.0, t = -100.0;  // burn-in from rest
    for (; t < 0.0; t += h) {
      const double yn = y + (-k * x - c * y + kDrive * u(t)) * h + std::sqrt(a22 * h) * normal(gen);
      x += y * h, y = yn;
    }
    Record rec;
    rec.id = r;
    rec.dt = dt;
    rec.offset = xs.size();
    rec.size = n;
    rec.source = "driven";
    for (std::size_t i = 0; i < n; ++i) {
      const double ti = double(i) * dt;
      xs.push_back(x), us.push_back(u(ti));
      for (int s = 0; s < sub; ++s) {
        const double ts = ti + s * h;
        const double yn = y + (-k * x - c * y + kDrive * u(ts)) * h + std::sqrt(a22 * h) * normal(gen);
        x += y * h, y = yn;
      }
    }
    d.records.push_back(rec);
  }
  d.x = Column(std::move(xs));
  d.u = Column(std::move(us));
  return d;
}

/// Writes `d` (with its input column) and a config of `keys`, runs identify-vehs (not quiet) and
/// returns the model file; `err` receives its stderr.
ModelFile identified(const Dataset& d, const std::string& name, const std::string& keys, std::string& err) {
  const fs::path dir = work_dir();
  const fs::path data = dir / (name + ".csv"), cfg = dir / (name + ".json"), out = dir / (name + "_model.json");
  write_measurements(data.string(), d, WriteColumns{false, d.has_u(), 17});
  std::ofstream(cfg) << R"({"data": ")" << data.string() << R"(", "output": ")" << out.string() << "\"" << keys << "}";
  fs::remove(out);
  const int code = run_identify({cfg.string()}, &err);
  INFO(err);
  REQUIRE(code == 0);
  return read_model_file(out.string());
}

}  // namespace

TEST_CASE("identify-vehs - default config: the data's input column enters the drift library as u - "
          "its coefficient within 3 SE of the truth - and the output says so",
          "[tools][identify][defaults]") {
  const Dataset d = driven_oscillator(4, 1000.0, 3);
  std::string err;
  const ModelFile f = identified(d, "driven_default", "", err);
  CHECK(err.find("the recorded input 'u' enters the default drift library as the term u") != std::string::npos);
  const Model& m = f.model;
  REQUIRE(m.drift_stderr.count("u") == 1);
  const double est = m.drift_coef("u"), se = m.drift_stderr.at("u");
  INFO("u: " << est << " +- " << se);
  CHECK(se < 0.1 * kDrive);
  CHECK(std::abs(est - kDrive) <= 3.0 * se);
  const auto& input = f.sections.at("data").at("input");
  CHECK(input.at("column") == "u");
  CHECK(input.at("in_drift_library") == true);
  CHECK(input.at("added") == true);
  CHECK(input.at("why").get<std::string>().find("default drift library") != std::string::npos);
}

TEST_CASE("identify-vehs: a given drift_library without u while the data have an input is warned about - "
          "in one line and in the model file",
          "[tools][identify][defaults]") {
  const Dataset d = driven_oscillator(1, 300.0, 4);
  std::string err;
  const ModelFile f = identified(d, "driven_no_u", R"(, "drift_library": ["x", "y"], "diffusion_library": ["1"])", err);
  CHECK(f.model.drift_stderr.count("u") == 0);
  const auto line = err.find("warning: ");
  REQUIRE(line != std::string::npos);
  const std::string warning = err.substr(line, err.find('\n', line) - line);  // one line
  CHECK(warning.find("the recorded input 'u' is not used") != std::string::npos);
  CHECK(warning.find("drift_library") != std::string::npos);
  CHECK(f.sections.at("data").at("input").at("in_drift_library") == false);
}

TEST_CASE("identify-vehs - estimator auto with the likelihood: it starts from every moment fit (uli and the "
          "auto choice among them) and refines the start with the highest log-likelihood",
          "[tools][identify][likelihood][defaults]") {
  // omega*dt 1.0: the sampling cannot vouch for the moment estimators, the likelihood refines
  const Dataset d = vehs_lik_test::simulate(vehs_lik_test::bistable(), 0.7, 2, 500.0, 11);
  std::string err;
  const ModelFile f = identified(
      d, "starts", R"(, "drift_library": ["1", "x", "x^2", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none")",
      err);
  REQUIRE(f.model.fit);
  REQUIRE(f.model.fit->likelihood);
  const auto& starts = f.sections.at("estimator").at("likelihood_starts");
  REQUIRE(starts.size() >= 3);
  std::vector<std::string> names;
  double best = -INFINITY, chosen = NAN;
  std::string chosen_name;
  for (const auto& s : starts) {
    names.push_back(s.at("start"));
    if (!s.contains("log_likelihood")) continue;
    const double ll = s.at("log_likelihood");
    best = std::max(best, ll);
    if (s.at("status") == "chosen") chosen = ll, chosen_name = s.at("start");
  }
  INFO(starts.dump());
  CHECK(names[0].rfind("auto: ", 0) == 0);  // the auto choice first
  CHECK(std::count_if(names.begin(), names.end(), [](const std::string& n) { return n == "uli" || n == "auto: uli"; }) == 1);
  CHECK(std::count(names.begin(), names.end(), "forward") + std::count(names.begin(), names.end(), "auto: forward") == 1);
  CHECK(chosen == best);
  // the model file's estimator is the chosen start's moment fit, and stderr lists every start
  const std::string est = enum_to_string(kEstimatorNames, f.model.fit->estimator);
  CHECK((chosen_name == est || chosen_name == "auto: " + est || chosen_name.rfind(est + " (", 0) == 0));
  for (const auto& n : names) CHECK(err.find("likelihood start " + n + ":") != std::string::npos);
}

TEST_CASE("identify-vehs: a named moment estimator keeps its single likelihood start",
          "[tools][identify][likelihood][defaults]") {
  const Dataset d = vehs_lik_test::simulate(vehs_lik_test::bistable(), 0.7, 1, 400.0, 12);
  std::string err;
  const ModelFile f = identified(d, "one_start",
                                 R"(, "drift_library": ["x", "x^3", "y"], "diffusion_library": ["1"], "sparsity": "none", )"
                                 R"("estimator": "uli", "likelihood": {"select": false})",
                                 err);
  REQUIRE(f.model.fit->likelihood);
  CHECK_FALSE(f.sections.at("estimator").contains("likelihood_starts"));
  CHECK(err.find("likelihood start") == std::string::npos);
}
