// simulate-vehs's free-run validation (src/tools/validation.cpp) and its input interpolation
// through the command line: a model validated on records it generated scores the integration
// error only, a wrong model does not; the input is applied as the model file says, in the
// validation and in the stochastic simulation alike; bad input (a sampling mismatch, a free run
// that diverges, a drive shorter than the records) gives one line and writes nothing.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "tools/tools.hpp"
#include "vehs/io/json_file.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "vehs/likelihood/free_run.hpp"
#include "vehs/likelihood/signals.hpp"
#include "vehs/sim/simulate.hpp"

namespace fs = std::filesystem;
using namespace vehs;

namespace {

fs::path work_dir() {
  const fs::path p = fs::path(VEHS_BINARY_DIR) / "test_validation_work";
  fs::create_directories(p);
  return p;
}

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

int run_simulate(const std::vector<std::string>& args, std::string* err = nullptr) {
  std::vector<std::string> a{"simulate-vehs"};
  a.insert(a.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : a) argv.push_back(s.data());
  std::ostringstream e;
  auto* old = std::cerr.rdbuf(e.rdbuf());
  const int code = tools::simulate_main(static_cast<int>(argv.size()), argv.data());
  std::cerr.rdbuf(old);
  if (err) *err = e.str();
  return code;
}

// a driven Duffing, almost noise-free (the validation scores the integration error only)
const char* kDriven = R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.2, "u": 1.0}, "diffusion": {"1": 1e-14}})";
const char* kWrongDamping = R"({"drift": {"x": -1.0, "x^3": -0.5, "y": -0.4, "u": 1.0}, "diffusion": {"1": 1e-14}})";

/// Records of the driven Duffing at dt 0.1 from the simulator (Taylor 1.5, 40 substeps, input
/// held over each interval), written with their input.
fs::path driven_records(const fs::path& dir) {
  const double dt = 0.1;
  const std::size_t n = 3000;
  sim::SimulationOptions o;
  o.dt = dt;
  o.substeps = 40;
  o.records = 1;
  o.samples = n;
  o.seed = 3;
  o.scheme = sim::Scheme::Taylor15;
  o.record_y = false;
  o.x0.uniform = false;
  o.x0.values = {0.3};
  o.drive = likelihood::random_phase_multisine(n, dt, 20, 0.1, 0.1, 11);
  const Dataset d = sim::simulate(model_from_json(nlohmann::json::parse(kDriven), "test"), o);
  const fs::path p = dir / "driven.csv";
  write_measurements(p.string(), d, WriteColumns{false, true, 17});
  return p;
}

std::string validate_config(const fs::path& data, const std::string& model, const fs::path& out,
                            const std::string& extra = "") {
  return R"({"model": )" + model + R"(, "validate": {"data": ")" + data.string() +
         R"(", "skip": 300, "substeps": 16, "output": ")" + out.string() + "\"" + extra + "}}";
}

}  // namespace

TEST_CASE("simulate-vehs validate: the generating model scores its integration error, a wrong one does not",
          "[tools][validation]") {
  const fs::path dir = work_dir();
  const fs::path data = driven_records(dir);
  const fs::path cfg = dir / "validate.json", out = dir / "validation.json";
  // deterministic: the process noise is ~1e-7 of the signal; the only errors are the initial
  // velocity from a one-sided difference (decayed by e^-3 after 300 samples) and RK4 vs Taylor 1.5
  write_text(cfg, validate_config(data, kDriven, out, R"(, "figure": false)"));
  fs::remove(out);
  REQUIRE(run_simulate({cfg.string(), "--quiet"}) == 0);
  const auto j = read_json_file(out.string(), "validation");
  const auto& s = j["segments"][0];
  CHECK(s["rmse"].get<double>() < 2e-3 * s["measured_rms"].get<double>());
  CHECK(fs::exists(dir / "validation_series.csv"));
  CHECK(j["input"] == "zoh");
  write_text(cfg, validate_config(data, kWrongDamping, out));
  REQUIRE(run_simulate({cfg.string(), "--quiet"}) == 0);
  const auto w = read_json_file(out.string(), "validation");
  CHECK(w["segments"][0]["rmse"].get<double>() > 0.05 * w["segments"][0]["measured_rms"].get<double>());
}

TEST_CASE("simulate-vehs applies the model file's input interpolation in the validation and in the simulation",
          "[tools][validation]") {
  const fs::path dir = work_dir();
  const double dt = 0.1;
  const std::size_t n = 600;
  // a drive whose zero-order hold and linear interpolation differ markedly (a slow multisine)
  const auto u = likelihood::random_phase_multisine(n, dt, 10, 0.3, 0.5, 5);
  Dataset drive;
  Record r;
  r.dt = dt;
  r.size = n;
  drive.records.push_back(r);
  drive.x = u;
  const fs::path drive_csv = dir / "drive.csv";
  write_measurements(drive_csv.string(), drive, WriteColumns{false, false, 17});
  nlohmann::json m = nlohmann::json::parse(kDriven);
  m["estimator"] = {{"input", "linear"}};
  const fs::path model = dir / "linear_model.json", cfg = dir / "sim.json", out = dir / "sim.csv";
  write_text(model, m.dump());
  write_text(cfg, R"({"model": ")" + model.string() + R"(", "trajectories": 1, "dt": 0.1, "duration": 60, "substeps": 20,
    "x0": [0.0], "record_velocity": false, "drive": {"path": ")" + drive_csv.string() + R"(", "column": "x"},
    "output": ")" + out.string() + "\"}");
  REQUIRE(run_simulate({cfg.string(), "--quiet"}) == 0);
  ReadOptions ro;
  ro.read_u = false;
  const Dataset sim = read_measurements(out.string(), ro);
  REQUIRE(sim.x.size() == n);
  const Model truth = model_from_json(m, "test");
  likelihood::FreeRunOptions fo;
  fo.substeps = 40;
  fo.input = InputInterpolation::Linear;
  const auto linear = likelihood::free_run(truth, {0.0, 0.0}, u, dt, n, fo);
  fo.input = InputInterpolation::ZeroOrderHold;
  const auto held = likelihood::free_run(truth, {0.0, 0.0}, u, dt, n, fo);
  double e_lin = 0, e_zoh = 0;
  for (std::size_t k = 0; k < n; ++k) {
    e_lin = std::max(e_lin, std::abs(sim.x[k] - linear[k]));
    e_zoh = std::max(e_zoh, std::abs(sim.x[k] - held[k]));
  }
  INFO("max |sim - linear| " << e_lin << ", max |sim - zoh| " << e_zoh);
  // deterministic (process noise ~1e-7): the simulated record follows the linear input, to the
  // O(dt/substeps) of holding it at midpoints, 10x closer than the held input's record
  CHECK(e_lin < 0.1 * e_zoh);
}

TEST_CASE("simulate-vehs validate and drive: bad input gives one line, a non-zero exit and no file",
          "[tools][validation][errors]") {
  const fs::path dir = work_dir();
  const fs::path data = driven_records(dir);
  const fs::path cfg = dir / "bad_validate.json", out = dir / "bad_validation.json";
  nlohmann::json fitted = nlohmann::json::parse(kDriven);
  fitted["sampling"] = {{"dt", 0.05}};
  struct Case { std::string model, extra, message; };
  const Case cases[] = {
      {fitted.dump(), "", "sampling mismatch"},
      {R"({"drift": {"x": -1.0, "y": 0.5, "u": 1.0}, "diffusion": {"1": 1e-14}})", "", "diverge"},
      {kDriven, R"(, "segments": [{"first": 10, "last": 5000}])", "'validate.segments[0].last'"},
      {kDriven, R"(, "input": "band_limited", "segments": [{"first": 0, "last": 10}])", "skip"},
  };
  for (const auto& c : cases) {
    CAPTURE(c.model, c.extra);
    write_text(cfg, validate_config(data, c.model, out, c.extra));
    fs::remove(out);
    fs::remove(dir / "bad_validation_series.csv");
    std::string err;
    CHECK(run_simulate({cfg.string(), "--quiet"}, &err) == 1);
    CHECK(err.find(c.message) != std::string::npos);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK(!fs::exists(out));
    CHECK(!fs::exists(dir / "bad_validation_series.csv"));
  }
  // a drive shorter than the records
  Dataset drive;
  Record r;
  r.dt = 0.1;
  r.size = 10;
  drive.records.push_back(r);
  drive.x.assign(10, 0.1);
  const fs::path short_drive = dir / "short_drive.csv", sim_out = dir / "short.csv";
  write_measurements(short_drive.string(), drive, WriteColumns{false, false, 17});
  write_text(cfg, std::string(R"({"model": )") + kDriven + R"(, "trajectories": 1, "dt": 0.1, "duration": 60,
    "drive": {"path": ")" + short_drive.string() + R"(", "column": "x"}, "output": ")" + sim_out.string() + "\"}");
  fs::remove(sim_out);
  std::string err;
  CHECK(run_simulate({cfg.string(), "--quiet"}, &err) == 1);
  CHECK(err.find("drive has 10 values") != std::string::npos);
  CHECK(!fs::exists(sim_out));
}
