// simulate-vehs configuration: every key documented, outputs written in the contract's formats,
// bad configs rejected with one-line errors naming the file and key.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>

#include "vehs/core/error.hpp"
#include "vehs/io/measurements.hpp"
#include "vehs/io/model_file.hpp"
#include "tools/simulate_tool.hpp"

namespace fs = std::filesystem;
using namespace vehs::sim;
using namespace vehs::tools;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("vehs_sim_test_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(file(name)) << text;
    return file(name);
  }
};

const char* kModel = R"({"drift": {"x": -1.0, "x^3": -1.0, "y": -0.5}, "diffusion": {"1": 0.2}})";

SimulateJob load_job(const std::string& path) {
  return simulate_job_from_config(vehs::tools::Config::load(path, simulate_schema()));
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const vehs::Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("--help documents every key, including the contract's", "[config]") {
  const auto& schema = simulate_schema();
  const std::string help = schema.help_text();
  for (const auto& k : schema.keys) {
    CHECK(help.find("  " + k.name + "  (") != std::string::npos);
    CHECK(k.help.size() > 10);
  }
  for (const char* k : {"model", "trajectories", "duration", "dt", "substeps", "scheme", "seed", "x0", "output",
                        "y0", "burn_in", "sensor_noise", "record_velocity", "drive", "statistics"})
    CHECK(schema.find(k) != nullptr);
}

TEST_CASE("a config runs and writes records and statistics in the contract's formats", "[config]") {
  TempDir dir;
  const std::string model = dir.write("model.json", kModel);
  const std::string cfg = dir.write("sim.json", R"({
    "model": ")" + model + R"(", "trajectories": 3, "duration": 2, "dt": 0.01, "substeps": 4,
    "scheme": "baoab", "seed": 5, "x0": [0.1, 0.2, 0.3], "y0": {"uniform": [-0.1, 0.1]},
    "output": ")" + dir.file("out/records.csv") + R"(",
    "statistics": {"output": ")" + dir.file("out/stats.json") + R"(", "discard": 0.5,
                   "grid": {"x": [-2, 2, 8], "y": [-1.5, 1.5, 6]}},
    "summary": ")" + dir.file("out/summary.json") + R"("})");
  const auto job = load_job(cfg);
  CHECK(job.options.samples == 200);
  CHECK(job.options.substeps == 4);
  CHECK(job.options.scheme == Scheme::Baoab);
  vehs::tools::AppOptions app;
  app.quiet = true;
  CHECK(run_simulate_job(job, app) == 0);
  const auto d = vehs::read_measurements(dir.file("out/records.csv"), [] {
    vehs::ReadOptions r;
    r.read_y = true;
    return r;
  }());
  REQUIRE(d.records.size() == 3);
  CHECK(d.records[1].size == 200);
  CHECK(d.records[1].dt == Approx(0.01));
  CHECK(d.x_of(d.records[2])[0] == 0.3);
  CHECK(d.has_y());
  CHECK(std::abs(d.y_of(d.records[0])[0]) <= 0.1);
  nlohmann::json st;
  std::ifstream(dir.file("out/stats.json")) >> st;
  for (const char* k : {"E[X^2]", "E[Y^2]", "E[XY]"}) {
    CHECK(st.contains(k));
    CHECK(st["stderr"].contains(k));
  }
  CHECK(st["samples_per_record"] == 150);
  CHECK(st["histograms"]["p(x,y)"] == "stats_pxy.csv");
  CHECK(st["simulation"]["scheme"] == "baoab");
  // cell-centred grid: first x centre at min + h/2
  std::ifstream pxy(dir.file("out/stats_pxy.csv"));
  std::string header, first;
  std::getline(pxy, header);
  std::getline(pxy, first);
  CHECK(header == "x,y,p");
  CHECK(std::stod(first.substr(0, first.find(','))) == Approx(-2 + 0.25));
  CHECK(fs::exists(dir.file("out/stats_px.csv")));
  CHECK(fs::exists(dir.file("out/summary.json")));

  // .npy output, statistics only, inline model
  const std::string cfg2 = dir.write("sim2.json", std::string(R"({"model": )") + kModel +
                                                      R"(, "trajectories": 2, "duration": 1, "dt": 0.01,
    "output": ")" + dir.file("records.npy") + R"("})");
  CHECK(run_simulate_job(load_job(cfg2), app) == 0);
  CHECK(vehs::read_measurements(dir.file("records.npy")).records.size() == 2);
}

TEST_CASE("a recorded drive is read from a measurement file", "[config]") {
  TempDir dir;
  std::string csv = "t,u\n";
  for (int i = 0; i < 300; ++i) csv += std::to_string(i * 0.01) + "," + std::to_string(std::sin(0.05 * i)) + "\n";
  const std::string drive = dir.write("drive.csv", csv);
  const std::string cfg = dir.write("sim.json", R"({"model": {"drift": {"x": -1.0, "y": -0.5, "u": 1.0}, "diffusion": {"1": 0.01}},
    "trajectories": 2, "duration": 2, "dt": 0.01, "drive": {"path": ")" + drive + R"("},
    "output": ")" + dir.file("o.csv") + R"("})");
  const auto job = load_job(cfg);
  CHECK(job.options.drive.size() == 300);
  vehs::tools::AppOptions app;
  app.quiet = true;
  CHECK(run_simulate_job(job, app) == 0);
  const auto d = vehs::read_measurements(dir.file("o.csv"));
  CHECK(d.has_u());
  // wrong sampling interval
  const std::string bad = dir.write("bad.json", R"({"model": {"drift": {"x": -1.0, "y": -0.5, "u": 1.0}, "diffusion": {"1": 0.01}},
    "trajectories": 2, "duration": 2, "dt": 0.005, "drive": {"path": ")" + drive + R"("}, "output": "x.csv"})");
  CHECK(error_of([&] { load_job(bad); }).find("sampled at") != std::string::npos);
}

TEST_CASE("an interpolated drive too large for the memory limit is refused before it is refined", "[config][errors]") {
  // one trajectory of 10^5 samples driven through the model fit's linear input on 2000 substeps:
  // the refined drive alone would be 2·10^8 values (1.6 GB), the records x and u as much again;
  // the simulator's limit (here 1 GB) refuses all of it before the drive is refined
  SimulateJob job;
  job.model = vehs::model_from_json(nlohmann::json::parse(
                                        R"({"drift": {"x": -1.0, "y": -0.5, "u": 1.0}, "diffusion": {"1": 0.01},
                                            "estimator": {"input": "linear"}})"),
                                    "model");
  REQUIRE(job.model.fit);
  job.options.dt = 0.1;
  job.options.samples = 100000;
  job.options.substeps = 2000;
  job.options.records = 1;
  job.options.record_y = false;
  job.options.memory_limit = 1e9;
  job.options.drive.resize(job.options.samples);
  for (std::size_t k = 0; k < job.options.drive.size(); ++k) job.options.drive[k] = std::sin(0.01 * static_cast<double>(k));
  // 4.8 GB counts the refined drive besides x and u (refined first, the simulator would say 3.2)
  const std::string what = error_of([&] { simulate_job(job, {}); });
  CHECK(what.find("simulation: the records would need 4.79995 GB of memory (limit 1 GB)") != std::string::npos);
  CHECK(what.find('\n') == std::string::npos);
}

TEST_CASE("bad simulate-vehs configs are rejected naming file and key", "[config][errors]") {
  TempDir dir;
  auto cfg = [&](const std::string& extra) {
    return dir.write("c.json", std::string(R"({"model": )") + kModel + R"(, "output": "o.csv")" + extra + "}");
  };
  CHECK(error_of([&] { load_job(cfg(R"(, "trajectorys": 3)")); }).find("did you mean 'trajectories'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "duration": 1.0005, "dt": 0.001)")); }).find("'duration'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "duration": 0.001, "dt": 0.001)")); }).find("2·dt") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "trajectories": 2, "x0": [1, 2, 3])")); }).find("'x0'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "x0": {"uniform": [1]})")); }).find("'x0'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "scheme": "rk4")")); }).find("must be one of") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "dt": -1)")); }).find("'dt'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "substeps": 0)")); }).find("'substeps'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "sensor_noise": -0.1)")); }).find("'sensor_noise'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "statistics": {"discard": 1})")); }).find("'statistics.output'") != std::string::npos);
  CHECK(error_of([&] { load_job(cfg(R"(, "statistics": {"output": "s.json", "grid": {"x": [1, 0, 5], "y": [0, 1, 5]}})")); })
            .find("min < max") != std::string::npos);
  const std::string none = dir.write("n.json", std::string(R"({"model": )") + kModel + "}");
  CHECK(error_of([&] { load_job(none); }).find("nothing would be written") != std::string::npos);
  const std::string neg = dir.write("neg.json", R"({"model": {"drift": {"x": -1.0}, "diffusion": {"1": -0.02}}, "output": "o.csv"})");
  const auto e = error_of([&] { load_job(neg); });
  CHECK(e.find("neg.json") != std::string::npos);
  CHECK(e.find("negative") != std::string::npos);
}
